// The calibration's fit: the bench model (servo_stand.h, closed-form solver)
// against a measurement, least squares over the base factors and the
// parameters of the effects in the model, with NLopt BOBYQA (derivative-free
// and bounded: several effects are not smooth in their parameter).
#pragma once

#include <utility>
#include <vector>

#include "analysis/calibration/effect_catalogue.h"
#include "analysis/calibration/measured_record.h"
#include "analysis/calibration/residual_stats.h"
#include "analysis/servo_bench/servo_stand.h"

namespace chainsim {

constexpr int kMaxEvalBase = 250;    // evaluations of a base (or final) refit
constexpr int kMaxEvalJoint = 400;   // evaluations of a fit with a new effect

// a measurement and how it is compared with the model
struct FitProblem {
  BenchConfig datasheet;
  MeasuredRecord m;
  double sa = 1, si = 1;   // normalisation: std of the measured angle / current
  BlockSplit split;
  mutable int model_runs = 0;   // model evaluations of the fits so far
};

// the problem for a measurement: the datasheet's step capped at 100 us (the
// scheme's own discretisation error, 0.09 degrees at 500 us, stays below the
// noise), the normalisation and the block split
FitProblem make_fit_problem(const BenchConfig& datasheet, MeasuredRecord m);

// the model's response to the measurement's set-points and its residual
struct ModelRun {
  std::vector<BenchSample> sim;
  Residual residual;
};
ModelRun run_model(const FitProblem& p, const BenchConfig& b);

struct Fit {
  std::vector<int> effects;    // catalogue indices
  std::vector<double> x;       // base factors, then the effects' parameters
  double train = 0, held = 0, white = 0, gap = 0;   // nrmse on the fitted set; held-out nrmse, whiteness, gap
  int evals = 0;
};

// least squares on `set` from x0 within the bounds (a discrete effect keeps
// its x0 value)
Fit fit_model(const FitProblem& p, const std::vector<int>& effects, std::vector<double> x0, Samples set,
              int max_eval);

// the fit with one more effect on the training blocks: its parameter from
// the best of its grid, then everything together, from two starts (the
// current base factors and the datasheet's); the better training fit
Fit fit_with_effect(const FitProblem& p, const Fit& base, int effect);

// 95 % intervals of f.x on all data (finite-difference Jacobian;
// residual_stats.h confidence_intervals)
std::vector<std::pair<double, double>> fit_intervals(const FitProblem& p, const Fit& f);

}  // namespace chainsim
