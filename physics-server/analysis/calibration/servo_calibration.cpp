// Servo calibration (servo_calibration.h), in order:
//  1. the measurement is cut into kCvBlocks time blocks; even blocks train,
//     odd blocks are held out (block cross-validation of a time series);
//  2. the base parameters are refitted on the training blocks (the search's
//     first round re-fits them from two starts);
//  3. every sample gets a regime, for the report's localisation and the
//     candidates' signatures;
//  4. the greedy search adds catalogue effects (effect_search.h);
//  5. verdict: a residual consistent with noise is explained (or
//     no_missing_effect when nothing was added); otherwise unexplained;
//  6. the gap before and after: the held-out structured error of the base and
//     of the search's model, against one white level (structured_errors);
//  7. the final model is refitted on all data for the reported parameters and
//     their 95 % intervals, and checked on the ODE stand.
#include "analysis/calibration/servo_calibration.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "analysis/calibration/paired_runs.h"
#include "analysis/calibration/regimes.h"
#include "analysis/calibration/text_format.h"

namespace chainsim {

ServoCalibration calibrate_servo(const BenchConfig& datasheet, MeasuredRecord measured,
                                 const CalibrationProgress& say) {
  ModelRuns runs;  // the calibration's own strand: its tasks' runs come back to it
  ServoCalibration c;
  c.problem = make_fit_problem(datasheet, std::move(measured));
  const FitProblem& p = c.problem;
  const size_t n = p.m.size();
  const double stall_a = p.datasheet.servo.supply_v / p.datasheet.servo.r;
  c.regime = classify_regimes(p.m, stall_a);
  say(std::to_string(n) + " samples, " + fmt_g(p.m.t.back() - p.m.t.front()) + " s; " +
      (p.m.has_current ? "angle and current" : "angle only") + "; " + std::to_string(kCvBlocks) +
      " blocks (even: fit, odd: held out)");

  const Residual r_data = run_model(runs, p, p.datasheet).residual;
  c.nrmse_datasheet = nrmse(r_data, p.split, Samples::held_out);
  // the loss's unit until the search re-estimates it from its models
  c.problem.noise = white_noise_scale(r_data, p.split);
  const Fit first = fit_model(runs, p, {}, std::vector<double>(kNumBase, 1.0), Samples::training, kMaxEvalBase);

  SearchState state;
  state.noise = p.noise;
  c.search = search_effects(runs, p, first, c.regime, state, say);
  // the final fit, its intervals and the report in the search's last unit
  c.problem.noise = state.noise;
  c.base = c.search.rounds.front().reference;
  const Fit& cur = c.search.model;
  c.verdict = cur.white <= kWhiteMax ? (cur.effects.empty() ? "no_missing_effect" : "explained") : "unexplained";

  c.final_fit = fit_model(runs, p, cur.effects, cur.x, Samples::all, kMaxEvalBase);
  c.final_fit.held_ci = cur.held_ci;
  c.ci = fit_intervals(runs, p, c.final_fit);
  c.before = run_model(runs, p, model_config(p.datasheet, {}, c.base.x));
  c.after = run_model(runs, p, model_config(p.datasheet, cur.effects, cur.x));
  std::tie(c.gap_before, c.gap_after) =
      structured_errors(c.before.residual, c.after.residual, p.split, Samples::held_out);
  say("datasheet model: held-out NRMSE " + fmt_g(c.nrmse_datasheet) + "; refitted base: " + fmt_g(c.base.held) +
      " (whiteness " + fmt_g(c.base.white, 3) + "); gap " + fmt_g(c.gap_before) + " -> " + fmt_g(c.gap_after) +
      " with the effects");
  for (const Fit& f : c.search.before)
    c.without.push_back(run_model(runs, p, model_config(p.datasheet, f.effects, f.x)));
  // the bench's own (ODE) stand with the final model, as a check of the fast solver
  const BenchConfig fin = model_config(p.datasheet, c.final_fit.effects, c.final_fit.x);
  const std::vector<BenchSample> ode = simulate_bench(fin, p.m.t, p.m.sp);
  const ModelRun fast = run_model(runs, p, fin);
  for (size_t k = 0; k < n; ++k)
    c.ode_check_max_angle_diff_deg =
        std::max(c.ode_check_max_angle_diff_deg, std::fabs(ode[k].angle_deg - fast.sim[k].angle_deg));
  c.model_runs = runs.count();
  say("verdict " + c.verdict + "; " + std::to_string(c.model_runs) + " model runs");
  return c;
}

}  // namespace chainsim
