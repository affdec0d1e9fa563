// The robot calibration's fits (robot_fit.h).
#include "analysis/robot_calibration/robot_fit.h"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace chainsim {

double speed_gap(const std::vector<double>& sim, const std::vector<SpeedRow>& rows, const std::vector<bool>& mask) {
  double s = 0;
  int n = 0;
  for (size_t i = 0; i < rows.size(); ++i)
    if (mask.empty() || mask[i]) s += (sim[i] - rows[i].real) * (sim[i] - rows[i].real), ++n;
  return n ? std::sqrt(s / n) : 0;
}

KnobFit fit_one_knob(const SpeedFunction& speeds, const std::vector<SpeedRow>& rows, const KnobSetting& fixed,
                     int k, const std::vector<bool>& mask) {
  const Knob& kb = robot_knobs()[k];
  const double a = std::log(kb.lo), b = std::log(kb.hi);
  int evals = 0;
  auto f = [&](double x) {
    KnobSetting st = fixed;
    st[k] = std::exp(x);
    ++evals;
    return speed_gap(speeds(st), rows, mask);
  };
  const int G = 7;
  double best = INFINITY, bx = 0;
  std::vector<double> xs(G), fs(G);
  for (int i = 0; i < G; ++i) {
    xs[i] = a + (b - a) * i / (G - 1), fs[i] = f(xs[i]);
    if (fs[i] < best) best = fs[i], bx = xs[i];
  }
  const int ib = int(std::min_element(fs.begin(), fs.end()) - fs.begin());
  double lo = xs[std::max(0, ib - 1)], hi = xs[std::min(G - 1, ib + 1)];
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c = hi - g * (hi - lo), d = lo + g * (hi - lo), fc = f(c), fd = f(d);
  for (int it = 0; it < 6; ++it) {
    if (fc < fd) hi = d, d = c, fd = fc, c = hi - g * (hi - lo), fc = f(c);
    else lo = c, c = d, fc = fd, d = lo + g * (hi - lo), fd = f(d);
  }
  for (auto [x, v] : {std::pair{c, fc}, std::pair{d, fd}})
    if (v < best) best = v, bx = x;
  KnobFit res;
  res.st = fixed;
  res.st[k] = std::exp(bx);
  res.gap = best;
  res.evals = evals;
  return res;
}

KnobFit fit_knobs(const SpeedFunction& speeds, const std::vector<SpeedRow>& rows, const KnobSetting& start,
                  const std::vector<bool>& mask, int max_eval) {
  std::vector<int> ks;
  std::vector<double> x, lb, ub;
  for (const auto& [k, v] : start) {
    ks.push_back(k);
    x.push_back(std::log(v));
    lb.push_back(std::log(robot_knobs()[k].lo)), ub.push_back(std::log(robot_knobs()[k].hi));
  }
  struct Ctx {
    const SpeedFunction* speeds;
    const std::vector<SpeedRow>* rows;
    const std::vector<int>* ks;
    const std::vector<bool>* mask;
    int evals = 0;
  } ctx{&speeds, &rows, &ks, &mask};
  auto obj = [](const std::vector<double>& xv, std::vector<double>&, void* p) {
    auto* c = static_cast<Ctx*>(p);
    KnobSetting st;
    for (size_t i = 0; i < xv.size(); ++i) st[(*c->ks)[i]] = std::exp(xv[i]);
    ++c->evals;
    return speed_gap((*c->speeds)(st), *c->rows, *c->mask);
  };
  nlopt::opt opt(x.size() >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_COBYLA, unsigned(x.size()));
  opt.set_lower_bounds(lb), opt.set_upper_bounds(ub);
  opt.set_min_objective(obj, &ctx);
  opt.set_maxeval(max_eval);
  opt.set_xtol_abs(0.005);
  std::vector<double> step(x.size());
  for (size_t i = 0; i < x.size(); ++i) step[i] = std::min(0.15, 0.25 * (ub[i] - lb[i]));
  opt.set_initial_step(step);
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], lb[i], ub[i]);
  double fx = NAN;
  try {
    opt.optimize(x, fx);
  } catch (const nlopt::roundoff_limited&) {
  } catch (const std::invalid_argument&) {
  }
  KnobFit res;
  for (size_t i = 0; i < ks.size(); ++i) res.st[ks[i]] = std::exp(x[i]);
  res.gap = speed_gap(speeds(res.st), rows, mask);
  // BOBYQA may end worse than where it started
  const double g0 = speed_gap(speeds(start), rows, mask);
  if (g0 < res.gap) res.st = start, res.gap = g0;
  res.evals = ctx.evals;
  return res;
}

KnobFit fit_new_knob(const SpeedFunction& speeds, const std::vector<SpeedRow>& rows, const KnobSetting& st0,
                     int new_knob, const std::vector<bool>& mask) {
  if (st0.empty()) return fit_one_knob(speeds, rows, {}, new_knob, mask);
  KnobFit one = fit_one_knob(speeds, rows, st0, new_knob, mask);
  KnobFit all = fit_knobs(speeds, rows, one.st, mask);
  all.evals += one.evals;
  return all;
}

}  // namespace chainsim
