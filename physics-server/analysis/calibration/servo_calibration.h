// Servo calibration: refit the servo's base parameters to a bench
// measurement, localise where the model disagrees, add effects from the
// servo model's catalogue while held-out data agree, and refit the final
// model on all data with 95 % intervals. docs/calibration.md.
//
//   measured_record.h   the measurement (CSV)
//   effect_catalogue.h  base factors and effects, applied to a BenchConfig
//   servo_fit.h         the least-squares fits (NLopt), from several starts
//   frame_clock.h       the pwm frame period and phase from the set-point changes' delays
//   residual_stats.h    block split, NRMSE, gap, whiteness, noise scale, intervals
//   selection_rule.h    the profile-likelihood and held-out tests of a candidate
//   regimes.h           regimes, regions, signatures
//   effect_search.h     the greedy search, variants
//   evidence_plots.h    where each accepted effect acts, before and after
//   calibration_report.h  report.json, report.md, SVG plots
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "analysis/calibration/effect_search.h"

namespace chainsim {

// the smallest measurement: four samples per cross-validation block
constexpr size_t kMinMeasuredRows = 4 * kCvBlocks;

struct ServoCalibration {
  FitProblem problem;            // its noise: the search's last loss unit (SearchState)
  std::vector<int> regime;       // classify_regimes of the measurement
  double nrmse_datasheet = 0;    // the datasheet model's held-out NRMSE
  Fit base;                      // the refitted base (no effects): the first round's reference
  EffectSearch search;           // search.model: base + accepted effects
  std::string verdict;           // explained, no_missing_effect or unexplained
  Fit final_fit;                 // search.model refitted on all data
  std::vector<std::pair<double, double>> ci;   // 95 % intervals of final_fit.x
  ModelRun before, after;        // base and search.model on all samples
  std::vector<ModelRun> without; // per accepted effect: the model before it (search.before) on all samples
  double gap_before = 0, gap_after = 0;  // held-out gaps of base and search.model, one white level
  double ode_check_max_angle_diff_deg = 0;     // final model: ODE stand vs the fast solver
  int model_runs = 0;            // model runs of the whole calibration
};

// the whole calibration; say gets progress lines
ServoCalibration calibrate_servo(const BenchConfig& datasheet, MeasuredRecord measured,
                                 const CalibrationProgress& say);

}  // namespace chainsim
