// The calibration's fit (servo_fit.h).
#include "analysis/calibration/servo_fit.h"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/calibration/frame_clock.h"
#include "analysis/calibration/paired_runs.h"

namespace chainsim {

FitProblem make_fit_problem(const BenchConfig& datasheet, MeasuredRecord m) {
  FitProblem p;
  p.datasheet = datasheet;
  p.datasheet.dt_us = std::min<int64_t>(p.datasheet.dt_us, 100);
  p.m = std::move(m);
  p.sa = std::max(stdev(p.m.angle), 1e-3);
  if (p.m.has_current) p.si = std::max(stdev(p.m.current), 1e-5);
  p.split = split_blocks(p.m.t);
  for (size_t k = 0; k < p.m.t.size(); ++k)
    if (p.split.in(k, Samples::training)) p.training_rows = k + 1;
  return p;
}

ModelRun run_model(ModelRuns& runs, const FitProblem& p, const BenchConfig& b, size_t rows) {
  ModelRun run;
  run.sim = runs.simulate(b, p.m.t, p.m.sp, rows);
  Residual& r = run.residual;
  const size_t n = run.sim.size();
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

Residual residual_at(ModelRuns& runs, const FitProblem& p, const std::vector<int>& effects,
                     const std::vector<double>& x, size_t rows = SIZE_MAX) {
  return run_model(runs, p, model_config(p.datasheet, effects, x), rows).residual;
}

double mean_loss(const std::vector<double>& loss, const BlockSplit& s, Samples set) {
  double sum = 0;
  size_t n = 0;
  for (size_t k = 0; k < loss.size(); ++k)
    if (s.in(k, set)) sum += loss[k], ++n;
  return n ? sum / n : 0.0;
}

// the mean loss on `set`; for the training blocks the model runs only as far
// as the last training sample (the held-out end block is not needed)
double set_loss(ModelRuns& runs, const FitProblem& p, const std::vector<int>& effects, const std::vector<double>& x,
                Samples set) {
  const Residual r = residual_at(runs, p, effects, x, set == Samples::training ? p.training_rows : SIZE_MAX);
  return mean_loss(sample_loss(r, p.noise), p.split, set);
}

// a parameter's bounds and scale in the optimiser
struct Bound {
  double lo, hi;
  bool log;
  double to_u(double x) const {
    const double u = log ? std::log(std::max(x, lo) / lo) / std::log(hi / lo) : (x - lo) / (hi - lo);
    return std::clamp(u, 0.0, 1.0);
  }
  double from_u(double u) const { return log ? lo * std::pow(hi / lo, u) : lo + u * (hi - lo); }
};

// the bounds of every parameter and which are free (not held). A frame
// clock found from the delays is held, or (clock_near, the fits) free within
// a narrow window around its value in x: the frame inside a model step
// drives that step in proportion (servo_model.cpp), so the loss is
// continuous in period and phase near the delays' estimate, and the phase
// and the base's speed, which trade off, are fitted together
void layout(const std::vector<int>& effects, const std::vector<double>* clock_near, std::vector<Bound>* bounds,
            std::vector<size_t>* free) {
  bounds->assign(kNumBase, Bound{kBaseFactorLo, kBaseFactorHi, false});
  for (int i = 0; i < kNumBase; ++i) free->push_back(i);
  for (int e : effects) {
    const Effect& ef = effect_catalogue()[e];
    for (size_t k = 0; k < ef.params.size(); ++k) {
      const EffectParam& q = ef.params[k];
      if (ef.fit == EffectFit::smooth) {
        free->push_back(bounds->size());
        bounds->push_back({q.lo, q.hi, q.log_scale});
      } else if (clock_near) {
        const double v = (*clock_near)[bounds->size()];
        // period and phase within their window; a pulse width's slope
        // (falling edge) within its bounds
        const double half = k == 0 ? kClockPeriodWindow * v : k == 1 ? kClockPhaseWindowMs : q.hi - q.lo;
        free->push_back(bounds->size());
        bounds->push_back({std::max(q.lo, v - half), std::min(q.hi, v + half), false});
      } else {
        bounds->push_back({q.lo, q.hi, q.log_scale});
      }
    }
  }
}

}  // namespace

Fit evaluate_fit(ModelRuns& runs, const FitProblem& p, const std::vector<int>& effects, const std::vector<double>& x,
                 Samples set) {
  Fit f;
  f.effects = effects;
  f.x = x;
  f.held_ci.assign(x.size(), {0.0, 0.0});
  const Residual r = residual_at(runs, p, effects, x);
  f.loss = sample_loss(r, p.noise);
  f.train = mean_loss(f.loss, p.split, set);
  f.sse_train = 0;
  for (size_t k = 0; k < f.loss.size(); ++k)
    if (p.split.in(k, Samples::training)) f.sse_train += f.loss[k];
  f.rho_train = residual_rho(r, p.noise, p.split, Samples::training);
  f.rho_held = residual_rho(r, p.noise, p.split, Samples::held_out);
  f.held = nrmse(r, p.split, Samples::held_out);
  f.white = whiteness(r, p.split, Samples::held_out);
  return f;
}

Fit fit_model(ModelRuns& runs, const FitProblem& p, const std::vector<int>& effects, std::vector<double> x0,
              Samples set, int max_eval, GiveUp* give_up) {
  std::vector<Bound> bounds;
  std::vector<size_t> free;
  layout(effects, &x0, &bounds, &free);
  const size_t n = free.size();
  std::vector<double> u(n);
  for (size_t i = 0; i < n; ++i) u[i] = bounds[free[i]].to_u(x0[free[i]]);
  // what the objective needs, through NLopt's data pointer: the strand the
  // fit's model runs are asked on among them
  struct Ctx {
    ModelRuns* runs;
    const FitProblem* p;
    const std::vector<int>* effects;
    const std::vector<Bound>* bounds;
    const std::vector<size_t>* free;
    std::vector<double> x;
    Samples set;
    GiveUp* give_up;
    nlopt::opt* opt;
    int evals = 0;
    double best = 1e300;
  };
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  Ctx ctx{&runs, &p, &effects, &bounds, &free, x0, set, give_up, &opt};
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(max_eval);
  opt.set_xtol_abs(1e-5);
  opt.set_ftol_rel(1e-7);
  opt.set_initial_step(std::vector<double>(n, 0.08));
  opt.set_min_objective(
      [](unsigned nn, const double* uu, double*, void* data) -> double {
        Ctx& c = *static_cast<Ctx*>(data);
        for (unsigned i = 0; i < nn; ++i) c.x[(*c.free)[i]] = (*c.bounds)[(*c.free)[i]].from_u(uu[i]);
        ++c.evals;
        const double loss = set_loss(*c.runs, *c.p, *c.effects, c.x, c.set);
        c.best = std::min(c.best, loss);
        if (c.give_up && c.evals == c.give_up->after && c.best > c.give_up->loss) {
          c.give_up->stopped = true;
          c.opt->force_stop();   // BOBYQA returns its best point so far
        }
        return loss;
      },
      &ctx);
  double fval = 0;
  try {
    opt.optimize(u, fval);
  } catch (const nlopt::roundoff_limited&) {
  } catch (const std::runtime_error&) {
  }
  std::vector<double> x = x0;
  for (size_t i = 0; i < n; ++i) x[free[i]] = bounds[free[i]].from_u(u[i]);
  Fit out = evaluate_fit(runs, p, effects, x, set);
  out.evals = ctx.evals;
  return out;
}

std::vector<double> datasheet_start(const std::vector<double>& x) {
  std::vector<double> s = x;
  std::fill(s.begin(), s.begin() + kNumBase, 1.0);
  return s;
}

Fit refit_from_starts(ModelRuns& runs, const FitProblem& p, const Fit& cur,
                      const std::vector<std::vector<double>>& starts, int max_eval) {
  std::vector<Fit> fits(starts.size());
  run_paired_each(runs, starts.size(), [&](ModelRuns& runs, size_t i) {
    fits[i] = fit_model(runs, p, cur.effects, starts[i], Samples::training, max_eval);
  });
  Fit best = cur;
  for (Fit& f : fits) {
    f.held_ci = cur.held_ci;
    if (f.train < best.train) best = std::move(f);
  }
  return best;
}

namespace {

// the phase (x[i], ms) that fits best on the training blocks, scanned over
// +-span_ms in steps of step_ms around its value (the latch moves in whole
// model steps, so the loss is piecewise constant in the phase: a scan, not
// the optimiser); x keeps the best
void scan_phase(ModelRuns& runs, const FitProblem& p, const std::vector<int>& eff, std::vector<double>* x, size_t i,
                double span_ms, double step_ms) {
  const double c = (*x)[i];
  std::vector<double> phase{c};   // the value now, then the scan's
  for (double d = -span_ms; d <= span_ms + 1e-9; d += step_ms) phase.push_back(std::max(0.0, c + d));
  std::vector<double> loss(phase.size());
  run_paired_each(runs, phase.size(), [&](ModelRuns& runs, size_t k) {
    std::vector<double> xt = *x;
    xt[i] = phase[k];
    loss[k] = set_loss(runs, p, eff, xt, Samples::training);
  });
  double best = loss[0], best_v = c;
  for (size_t k = 1; k < phase.size(); ++k)
    if (loss[k] < best - 1e-12) best = loss[k], best_v = phase[k];
  (*x)[i] = best_v;
}

// a frame clock's parameters from x: the phase (x[ip]) and the base's speed
// trade off (a later frame looks like a slower servo), so they are fitted
// together, then the phase scanned, until it stays; a fit that stops at the
// screen is fitted no further (*stopped). The fit at the final x, with the
// fits' model runs as its evals (not the scans')
Fit fit_clock_and_phase(ModelRuns& runs, const FitProblem& p, const std::vector<int>& eff, std::vector<double> x,
                        size_t ip, const GiveUp* screen, bool* stopped) {
  GiveUp g = screen ? *screen : GiveUp{};
  int evals = 0;
  for (int turn = 0; turn < 3; ++turn) {
    const Fit f = fit_model(runs, p, eff, x, Samples::training, kMaxEvalJoint, screen && turn == 0 ? &g : nullptr);
    x = f.x;
    evals += f.evals;
    if (g.stopped) break;
    scan_phase(runs, p, eff, &x, ip, 0.5, 0.05);
    if (std::fabs(x[ip] - f.x[ip]) < 0.01) break;
  }
  *stopped = g.stopped;
  Fit out = evaluate_fit(runs, p, eff, x);
  out.evals = evals;
  return out;
}

// a clock parameter's interval (ms): the delays' least-squares one (ci_s,
// about their estimate est_s, in s), widened to reach the fitted value v
std::pair<double, double> widened(double v, std::pair<double, double> ci_s, double est_s) {
  const double w = std::max(0.5 * 1e3 * (ci_s.second - ci_s.first), std::fabs(v - 1e3 * est_s));
  return std::make_pair(v - w, v + w);
}

// a frame clock on top of ref: its period and phase from the set-point
// changes' delays against two models without it (the reference, which may
// have bent its base to mimic the delay, and the datasheet base), from every
// change and from the large steps alone (frame_clocks_for), then per
// clock found: the phase scanned against the model (the delays carry the
// base's timing error; the scan finds the right frame edge, farther than the
// fit's window), the base fitted together with period and phase within
// their window (layout), the phase scanned again; the better training fit
Fit fit_frame_clock_effect(ModelRuns& runs, const FitProblem& p, const Fit& ref, int effect, GiveUp* screen) {
  const Effect& ef = effect_catalogue()[effect];
  std::vector<int> eff = ref.effects;
  eff.push_back(effect);
  const size_t ip = param_count(ref.effects) + 1;   // the phase
  Fit best;
  best.valid = false;
  // under the screen every clock found, from either start, is screened in
  // its own first fit: the reference's base may show no clock, or a wrong
  // one, where it has bent its timing to mimic the frames
  struct Clock {
    std::vector<double> base;
    FrameClockFit fc;
    Fit fit;
    bool stopped = false;
  };
  std::vector<Clock> clocks;
  for (int start = 0; start < 2; ++start) {
    const std::vector<double> base = start == 0 ? ref.x : datasheet_start(ref.x);
    for (const FrameClockFit& fc : frame_clocks_for(runs, p, model_config(p.datasheet, ref.effects, base)))
      clocks.push_back({base, fc, Fit{}, false});
  }
  // each clock's fit (independent of the others: two at a time)
  run_paired_each(runs, clocks.size(), [&](ModelRuns& runs, size_t c) {
    Clock& ck = clocks[c];
    std::vector<double> x = ck.base;
    x.push_back(ck.fc.clock.period_s * 1e3);
    x.push_back(ck.fc.clock.phase_s * 1e3);
    scan_phase(runs, p, eff, &x, ip, 1.5, 0.1);
    ck.fit = fit_clock_and_phase(runs, p, eff, x, ip, screen, &ck.stopped);
  });
  for (Clock& ck : clocks) {
    Fit& f = ck.fit;
    const FrameClockFit& fc = ck.fc;
    if (!best.valid || f.train < best.train) {
      // the intervals: the delays' least-squares ones, widened to reach
      // the fitted values
      const double per = f.x[ip - 1], ph = f.x[ip];
      best = std::move(f);
      best.held_ci = ref.held_ci;
      best.held_ci.push_back(widened(per, fc.period_ci_s, fc.clock.period_s));
      best.held_ci.push_back(widened(ph, fc.phase_ci_s, fc.clock.phase_s));
    }
  }
  if (screen && !clocks.empty() && std::all_of(clocks.begin(), clocks.end(), [](const Clock& c) { return c.stopped; }))
    screen->stopped = true;
  if (best.valid) return best;
  Fit f = evaluate_fit(runs, p, ref.effects, ref.x);
  f.effects = eff;
  for (const EffectParam& q : ef.params) f.x.push_back(q.lo);
  f.held_ci.resize(f.x.size(), {0.0, 0.0});
  f.valid = false;
  return f;
}

// the mean of the set-points the changes go to (90 deg without changes): a
// plain clock fitted to a falling-edge decoder latches at the falling edge
// of that set-point's pulse, so its frames are that pulse later than the
// decoder's
double mean_change_setpoint(const FitProblem& p) {
  double mean_sp = 0;
  const std::vector<SetpointChange> ch = setpoint_changes(p.m);
  for (const SetpointChange& c : ch) mean_sp += p.m.sp[c.k];
  return ch.empty() ? 90.0 : mean_sp / static_cast<double>(ch.size());
}

// that pulse (ms), for a slope k (us/deg)
double mean_pulse_ms(double mean_sp, double k_us_per_deg) { return 1.5 + 1e-3 * k_us_per_deg * (mean_sp - 90.0); }

// the falling-edge form (pulse width 1.5 ms + k (sp - 90 deg), acting at
// its falling edge), from two kinds of start:
// * the clock of the form it refines (`refined`, fitted on top of ref;
//   fitted here when null), where that clock was found: its latch times are
//   the falling edges of the mean set-point's pulse, so the frames start
//   earlier by that pulse's width. Each slope k of a few physical
//   conventions is tried with the phase moved so, and scanned;
// * the frame clocks of the delays less each change's pulse width for each
//   of those slopes (pulse_clocks_for), against ref's base and the
//   datasheet's: where the pulse widths spread the delays, the plain clock
//   may not be found at all, or be a compromise, while the corrected delays
//   make the frames' clock.
// From the best start by the training loss the base, period, phase and k
// are fitted together as the clock's fit does
Fit fit_falling_edge(ModelRuns& runs, const FitProblem& p, const Fit& ref, int effect, GiveUp* screen,
                     const Fit* refined) {
  const Effect& ef = effect_catalogue()[effect];
  Fit plain;
  if (!refined) {
    const std::vector<int> forms = effect_variants(ef.name);
    int at = -1;
    for (int v : forms)
      if (std::string(effect_catalogue()[v].variant) == ef.refines) at = v;
    plain = fit_frame_clock_effect(runs, p, ref, at, nullptr);
    refined = &plain;
  }
  std::vector<int> eff = ref.effects;
  eff.push_back(effect);
  const size_t ip = param_count(ref.effects) + 1;   // the phase; ip + 1: k
  const std::vector<double> slopes = {2.8, 5.6, 11.1, 16.7};   // us/deg
  const double mean_sp = mean_change_setpoint(p);
  auto frame_phase = [&](double latch_ms, double period_ms, double k) {
    return wrap_to_period(latch_ms - mean_pulse_ms(mean_sp, k), period_ms);
  };
  struct Start {
    std::vector<double> x;
    double span_ms = 1.5;   // the phase scan's
    const FrameClockFit* clock = nullptr;   // the corrected delays' clock (none: refined's)
  };
  std::vector<Start> starts;
  if (refined->valid)
    for (double k : slopes) {
      Start s{refined->x, 1.5, nullptr};
      s.x[ip] = frame_phase(refined->x[ip], refined->x[ip - 1], k);
      s.x.push_back(k);
      starts.push_back(std::move(s));
    }
  std::vector<PulseClock> pulse[2];
  for (int b = 0; b < 2; ++b) {
    const std::vector<double> base = b == 0 ? ref.x : datasheet_start(ref.x);
    pulse[b] = pulse_clocks_for(runs, p, model_config(p.datasheet, ref.effects, base), slopes);
    for (const PulseClock& pc : pulse[b]) {
      Start s{base, 0.5, &pc.fit};
      s.x.push_back(1e3 * pc.fit.clock.period_s);
      s.x.push_back(1e3 * pc.fit.clock.phase_s);
      s.x.push_back(pc.k_us_per_deg);
      starts.push_back(std::move(s));
    }
  }
  if (starts.empty()) {
    Fit f = *refined;
    f.effects = eff;
    f.x.resize(param_count(ref.effects));
    for (const EffectParam& q : ef.params) f.x.push_back(q.lo);
    f.held_ci.resize(f.x.size(), {0.0, 0.0});
    f.valid = false;
    return f;
  }
  // (each scan pairs its own runs)
  std::vector<double> loss(starts.size());
  for (size_t k = 0; k < starts.size(); ++k) {
    scan_phase(runs, p, eff, &starts[k].x, ip, starts[k].span_ms, 0.1);
    loss[k] = set_loss(runs, p, eff, starts[k].x, Samples::training);
  }
  const size_t best = static_cast<size_t>(std::min_element(loss.begin(), loss.end()) - loss.begin());
  bool stopped = false;
  Fit f = fit_clock_and_phase(runs, p, eff, starts[best].x, ip, screen, &stopped);
  if (screen) screen->stopped = stopped;
  const std::vector<double>& x = f.x;
  // intervals: period and phase from the clock the start came from (the
  // refined form's, or the corrected delays' least-squares ones), widened
  // to reach the fitted values; k from the curvature of the training loss
  // (-2 log-likelihood in noise units) at +-0.5 us/deg, inflated by the
  // residual's correlation
  const FrameClockFit* fc = starts[best].clock;
  f.held_ci = fc ? ref.held_ci : refined->held_ci;
  f.held_ci.resize(x.size(), {0.0, 0.0});
  if (fc) {
    f.held_ci[ip - 1] = widened(x[ip - 1], fc->period_ci_s, fc->clock.period_s);
    f.held_ci[ip] = widened(x[ip], fc->phase_ci_s, fc->clock.phase_s);
  } else {
    const double ph0 = refined->x[ip];
    const std::pair<double, double> pci =
        refined->held_ci.size() > ip ? refined->held_ci[ip] : std::make_pair(ph0, ph0);
    const double pw = std::max(0.5 * (pci.second - pci.first), 0.0);
    f.held_ci[ip] = {x[ip] - pw, x[ip] + pw};
  }
  const double dk = 0.5, kk = x[ip + 1];
  std::vector<double> xp = x, xm = x;
  xp[ip + 1] = std::min(ef.params[2].hi, kk + dk);
  xm[ip + 1] = std::max(ef.params[2].lo, kk - dk);
  const double sp = evaluate_fit(runs, p, eff, xp).sse_train, sm = evaluate_fit(runs, p, eff, xm).sse_train;
  const double hp = xp[ip + 1] - kk, hm = kk - xm[ip + 1];
  double sd = ef.params[2].hi - ef.params[2].lo;
  if (hp > 0 && hm > 0) {
    const double c2 = 2 * ((sp - f.sse_train) / hp + (sm - f.sse_train) / hm) / (hp + hm);
    const double rho = std::clamp(f.rho_train, 0.0, 0.999);
    if (c2 > 0) sd = std::sqrt(2.0 / c2 * (1 + rho) / (1 - rho));
  }
  f.held_ci[ip + 1] = {kk - 1.96 * sd, kk + 1.96 * sd};
  return f;
}

}  // namespace

// Why two starts: the reference was refitted without the new effect, so it
// has absorbed what it could of it (a missing Coulomb friction pulls Km = Kt
// down, R up and the load inertia to its bound), and from there a local
// optimiser can stay in that compensated basin: the least-squares objective
// is multimodal, for the generator's own physics as much as for the model
// (docs/calibration.md, "Limits"). The effects already accepted keep their
// values in the datasheet start.
Fit fit_effect_start(ModelRuns& runs, const FitProblem& p, const Fit& ref, int effect, int start, GiveUp* screen,
                     const Fit* refined) {
  const Effect& ef = effect_catalogue()[effect];
  std::vector<int> eff = ref.effects;
  eff.push_back(effect);
  std::vector<double> base = start == 0 ? ref.x : datasheet_start(ref.x);
  // a refining form's first start: the refined form's solution, its extra
  // parameters from the catalogue's starts
  const size_t shared = start == 0 && refined ? refined->x.size() - base.size() : 0;
  if (shared) base = refined->x;
  std::vector<std::vector<double>> xs;
  for (const std::vector<double>& tail : ef.starts) {
    xs.push_back(base);
    xs.back().insert(xs.back().end(), tail.begin() + static_cast<long>(shared), tail.end());
  }
  std::vector<double> m(xs.size(), 0.0);
  if (xs.size() > 1)
    run_paired_each(runs, xs.size(),
                    [&](ModelRuns& runs, size_t k) { m[k] = set_loss(runs, p, eff, xs[k], Samples::training); });
  std::vector<double> x;
  double best_start = 1e300;
  for (size_t k = 0; k < xs.size(); ++k)
    if (m[k] < best_start) best_start = m[k], x = xs[k];
  Fit f = fit_model(runs, p, eff, x, Samples::training, kMaxEvalJoint, start == 0 ? screen : nullptr);
  f.held_ci = ref.held_ci;
  f.held_ci.resize(f.x.size(), {0.0, 0.0});
  return f;
}

Fit fit_with_effect(ModelRuns& runs, const FitProblem& p, const Fit& ref, int effect, GiveUp* screen,
                    const Fit* refined) {
  if (effect_catalogue()[effect].fit == EffectFit::frame_clock)
    return *effect_catalogue()[effect].refines ? fit_falling_edge(runs, p, ref, effect, screen, refined)
                                              : fit_frame_clock_effect(runs, p, ref, effect, screen);
  Fit best = fit_effect_start(runs, p, ref, effect, 0, screen, refined);
  if (screen && screen->stopped) return best;
  Fit f = fit_effect_start(runs, p, ref, effect, 1);
  if (f.train < best.train) return f;
  return best;
}

Fit refit_plain_clock(ModelRuns& runs, const FitProblem& p, const Fit& ref, int plain, const Fit& falling) {
  std::vector<int> eff = ref.effects;
  eff.push_back(plain);
  const size_t ip = param_count(ref.effects) + 1;   // the phase
  // the falling-edge solution's latch of the mean set-point's pulse
  const double latch =
      wrap_to_period(falling.x[ip] + mean_pulse_ms(mean_change_setpoint(p), falling.x[ip + 1]), falling.x[ip - 1]);
  std::vector<double> x(falling.x.begin(), falling.x.begin() + static_cast<long>(ip + 1));
  x[ip] = latch;
  scan_phase(runs, p, eff, &x, ip, 0.5, 0.1);
  bool stopped = false;
  Fit f = fit_clock_and_phase(runs, p, eff, x, ip, nullptr, &stopped);
  // intervals: the base's as the falling-edge fit's; period and phase the
  // falling-edge fit's widths, about the refitted values, widened to reach
  // where that fit put them (its phase moved to the latch)
  f.held_ci = falling.held_ci;
  f.held_ci.resize(ip + 1, {0.0, 0.0});
  for (const auto& [i, from] : {std::make_pair(ip - 1, falling.x[ip - 1]), std::make_pair(ip, latch)}) {
    const std::pair<double, double> ci = i < falling.held_ci.size() ? falling.held_ci[i] : std::make_pair(0.0, 0.0);
    const double w = std::max(0.5 * (ci.second - ci.first), std::fabs(f.x[i] - from));
    f.held_ci[i] = {f.x[i] - w, f.x[i] + w};
  }
  return f;
}

Fit refit_frame_clock(ModelRuns& runs, const FitProblem& p, const Fit& f) {
  size_t j = 0;
  while (j < f.effects.size() && effect_catalogue()[f.effects[j]].fit != EffectFit::frame_clock) ++j;
  // none, or found last: already fitted on top of all the others
  if (j + 1 >= f.effects.size()) return f;
  // the model without the clock, then the clock fitted on top of it again
  // (it comes back last: its parameters are rotated back to their place)
  const auto off = static_cast<long>(param_offset(f.effects, j));
  const auto n = static_cast<long>(effect_catalogue()[f.effects[j]].params.size());
  Fit without = f;
  without.effects.erase(without.effects.begin() + static_cast<long>(j));
  without.x.erase(without.x.begin() + off, without.x.begin() + off + n);
  if (static_cast<long>(without.held_ci.size()) >= off + n)
    without.held_ci.erase(without.held_ci.begin() + off, without.held_ci.begin() + off + n);
  Fit again = fit_with_effect(runs, p, without, f.effects[j]);
  if (!again.valid || !(again.train < f.train)) return f;
  // the same model in f's order (the order of effects does not change it,
  // so again's statistics stand)
  again.effects = f.effects;
  std::rotate(again.x.begin() + off, again.x.end() - n, again.x.end());
  if (static_cast<long>(again.held_ci.size()) >= off + n)
    std::rotate(again.held_ci.begin() + off, again.held_ci.end() - n, again.held_ci.end());
  return again;
}

std::vector<std::pair<double, double>> fit_intervals(ModelRuns& runs, const FitProblem& p, const Fit& f) {
  std::vector<Bound> bounds;
  std::vector<size_t> free;
  layout(f.effects, nullptr, &bounds, &free);
  const Residual r0 = residual_at(runs, p, f.effects, f.x);
  const size_t m = r0.size();
  const int nch = r0.channels();
  const double wa = 1.0 / p.noise.angle, wi = 1.0 / p.noise.current;
  Eigen::MatrixXd J(m * nch, free.size());
  Eigen::VectorXd r(m * nch);
  for (size_t k = 0; k < m; ++k) {
    r(k) = wa * r0.angle[k];
    if (nch == 2) r(m + k) = wi * r0.current[k];
  }
  std::vector<double> xf(free.size());
  // each free parameter's two sides, x[2c] = plus, x[2c + 1] = minus
  std::vector<std::vector<double>> xs(2 * free.size(), f.x);
  for (size_t c = 0; c < free.size(); ++c) {
    const size_t i = free[c];
    xf[c] = f.x[i];
    const Bound& b = bounds[i];
    const double hstep = i < kNumBase ? 0.01 : std::max(0.02 * std::fabs(f.x[i]), 0.002 * (b.hi - b.lo));
    std::vector<double>&xp = xs[2 * c], &xm = xs[2 * c + 1];
    xp[i] += hstep;
    xm[i] -= hstep;
    if (i >= kNumBase && xm[i] < std::max(0.0, b.lo)) xm[i] = std::max(0.0, b.lo), xp[i] = xm[i] + 2 * hstep;
  }
  std::vector<Residual> rs(xs.size());
  run_paired_each(runs, xs.size(), [&](ModelRuns& runs, size_t k) { rs[k] = residual_at(runs, p, f.effects, xs[k]); });
  for (size_t c = 0; c < free.size(); ++c) {
    const size_t i = free[c];
    const std::vector<double>&xp = xs[2 * c], &xm = xs[2 * c + 1];
    const Residual &rp = rs[2 * c], &rm = rs[2 * c + 1];
    for (size_t k = 0; k < m; ++k) {
      J(k, c) = wa * (rp.angle[k] - rm.angle[k]) / (xp[i] - xm[i]);
      if (nch == 2) J(m + k, c) = wi * (rp.current[k] - rm.current[k]) / (xp[i] - xm[i]);
    }
  }
  const auto ci_free = confidence_intervals(J, r, m, xf, kNumBase);
  std::vector<std::pair<double, double>> ci(f.x.size());
  for (size_t i = 0; i < f.x.size(); ++i) ci[i] = i < f.held_ci.size() ? f.held_ci[i] : std::make_pair(f.x[i], f.x[i]);
  for (size_t c = 0; c < free.size(); ++c) ci[free[c]] = ci_free[c];
  return ci;
}

}  // namespace chainsim
