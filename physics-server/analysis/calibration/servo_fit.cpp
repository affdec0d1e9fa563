// The calibration's fit (servo_fit.h).
#include "analysis/calibration/servo_fit.h"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chainsim {

FitProblem make_fit_problem(const BenchConfig& datasheet, MeasuredRecord m) {
  FitProblem p;
  p.datasheet = datasheet;
  p.datasheet.dt_us = std::min<int64_t>(p.datasheet.dt_us, 100);
  p.m = std::move(m);
  p.sa = std::max(stdev(p.m.angle), 1e-3);
  if (p.m.has_current) p.si = std::max(stdev(p.m.current), 1e-5);
  p.split = split_blocks(p.m.t);
  return p;
}

ModelRun run_model(const FitProblem& p, const BenchConfig& b) {
  ModelRun run;
  run.sim = simulate_bench(b, p.m.t, p.m.sp, BenchSolver::closed_form);
  Residual& r = run.residual;
  const size_t n = p.m.t.size();
  r.has_current = p.m.has_current;
  r.angle.resize(n);
  r.current.assign(n, 0.0);
  for (size_t k = 0; k < n; ++k) {
    r.angle[k] = (run.sim[k].angle_deg - p.m.angle[k]) / p.sa;
    if (p.m.has_current) r.current[k] = (run.sim[k].current_a - p.m.current[k]) / p.si;
    if (!std::isfinite(r.angle[k]) || !std::isfinite(r.current[k])) r.finite = false;
  }
  return run;
}

namespace {

Residual residual_at(const FitProblem& p, const std::vector<int>& effects, const std::vector<double>& x) {
  return run_model(p, model_config(p.datasheet, effects, x)).residual;
}

}  // namespace

Fit fit_model(const FitProblem& p, const std::vector<int>& effects, std::vector<double> x0, Samples set,
              int max_eval) {
  const size_t n = x0.size();
  std::vector<double> lo(n), hi(n);
  for (int i = 0; i < kNumBase; ++i) lo[i] = kBaseFactorLo, hi[i] = kBaseFactorHi;
  for (size_t e = 0; e < effects.size(); ++e) {
    const Effect& ef = effect_catalogue()[effects[e]];
    lo[kNumBase + e] = ef.lo;
    hi[kNumBase + e] = ef.hi;
    if (ef.discrete) lo[kNumBase + e] = hi[kNumBase + e] = x0[kNumBase + e];
  }
  // scaled variables: u = (x - lo)/(hi - lo) in [0, 1]
  std::vector<double> u(n);
  for (size_t i = 0; i < n; ++i)
    u[i] = hi[i] > lo[i] ? std::clamp((x0[i] - lo[i]) / (hi[i] - lo[i]), 0.0, 1.0) : 0.0;
  struct Ctx {
    const FitProblem* p;
    const std::vector<int>* effects;
    const std::vector<double>*lo, *hi;
    Samples set;
    int evals = 0;
  } ctx{&p, &effects, &lo, &hi, set};
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(max_eval);
  opt.set_xtol_abs(1e-5);
  opt.set_ftol_rel(1e-7);
  opt.set_initial_step(std::vector<double>(n, 0.08));
  opt.set_min_objective(
      [](unsigned nn, const double* uu, double*, void* data) -> double {
        Ctx& c = *static_cast<Ctx*>(data);
        std::vector<double> x(nn);
        for (unsigned i = 0; i < nn; ++i) x[i] = (*c.lo)[i] + uu[i] * ((*c.hi)[i] - (*c.lo)[i]);
        ++c.evals;
        const double m = nrmse(residual_at(*c.p, *c.effects, x), c.p->split, c.set);
        return m * m;
      },
      &ctx);
  double f = 0;
  try {
    opt.optimize(u, f);
  } catch (const nlopt::roundoff_limited&) {
  } catch (const std::runtime_error&) {
  }
  Fit out;
  out.effects = effects;
  out.x.resize(n);
  for (size_t i = 0; i < n; ++i) out.x[i] = lo[i] + u[i] * (hi[i] - lo[i]);
  const Residual r = residual_at(p, effects, out.x);
  out.train = nrmse(r, p.split, set);
  out.held = nrmse(r, p.split, Samples::held_out);
  out.white = whiteness(r, p.split, Samples::held_out);
  out.gap = structured_error(r, p.split, Samples::held_out);
  out.evals = ctx.evals;
  p.model_runs += ctx.evals;
  return out;
}

// Why two starts: the current base was refitted without the new effect, so
// it has absorbed what it could of it (a missing Coulomb friction pulls Km =
// Kt down, R up and the load inertia to its bound), and from there a local
// optimiser can stay in that compensated basin: the least-squares objective
// is multimodal, for the generator's own physics as much as for the model
// (docs/calibration.md, "Limits"). The effects already accepted keep their
// values in the datasheet start.
Fit fit_with_effect(const FitProblem& p, const Fit& base, int effect) {
  const Effect& ef = effect_catalogue()[effect];
  std::vector<int> eff = base.effects;
  eff.push_back(effect);
  Fit best_fit;
  bool have = false;
  for (int start = 0; start < 2; ++start) {
    std::vector<double> x = base.x;
    if (start == 1) std::fill(x.begin(), x.begin() + kNumBase, 1.0);
    x.push_back(0.0);
    double best = 1e300, best_v = ef.grid[0];
    for (double v : ef.grid) {
      x.back() = v;
      const double m = nrmse(residual_at(p, eff, x), p.split, Samples::training);
      ++p.model_runs;
      if (m < best) best = m, best_v = v;
    }
    x.back() = best_v;
    Fit f = fit_model(p, eff, x, Samples::training, kMaxEvalJoint);
    if (!have || f.train < best_fit.train) best_fit = std::move(f), have = true;
  }
  return best_fit;
}

std::vector<std::pair<double, double>> fit_intervals(const FitProblem& p, const Fit& f) {
  const size_t n = f.x.size();
  const Residual r0 = residual_at(p, f.effects, f.x);
  const size_t m = r0.size();
  const int nch = r0.channels();
  Eigen::MatrixXd J(m * nch, n);
  Eigen::VectorXd r(m * nch);
  for (size_t k = 0; k < m; ++k) {
    r(k) = r0.angle[k];
    if (nch == 2) r(m + k) = r0.current[k];
  }
  for (size_t i = 0; i < n; ++i) {
    double hstep;
    if (i < kNumBase) {
      hstep = 0.01;
    } else {
      const Effect& e = effect_catalogue()[f.effects[i - kNumBase]];
      hstep = std::max(0.02 * std::fabs(f.x[i]), 0.002 * (e.hi - e.lo));
    }
    std::vector<double> xp = f.x, xm = f.x;
    xp[i] += hstep;
    xm[i] -= hstep;
    if (i >= kNumBase && xm[i] < 0) xm[i] = 0, xp[i] = 2 * hstep;  // stay at >= 0
    const Residual rp = residual_at(p, f.effects, xp);
    const Residual rm = residual_at(p, f.effects, xm);
    for (size_t k = 0; k < m; ++k) {
      J(k, i) = (rp.angle[k] - rm.angle[k]) / (xp[i] - xm[i]);
      if (nch == 2) J(m + k, i) = (rp.current[k] - rm.current[k]) / (xp[i] - xm[i]);
    }
  }
  return confidence_intervals(J, r, m, f.x, kNumBase);
}

}  // namespace chainsim
