// The calibration's fit: the bench model (servo_stand.h, closed-form solver)
// against a measurement, least squares in noise units over the base factors
// and the parameters of the effects in the model, with NLopt BOBYQA
// (derivative-free and bounded: several effects are not smooth in their
// parameter), from several starts.
#pragma once

#include <utility>
#include <vector>

#include "analysis/calibration/effect_catalogue.h"
#include "analysis/calibration/measured_record.h"
#include "analysis/calibration/paired_runs.h"
#include "analysis/calibration/residual_stats.h"
#include "analysis/servo_bench/servo_stand.h"

namespace chainsim {

constexpr int kMaxEvalBase = 250;    // evaluations of a refit from one start
constexpr int kMaxEvalJoint = 300;   // evaluations of a fit with a new effect from one start
// a fit moves a frame clock found from the delays by at most this much:
// its period by a fraction (0.2 %: 8 ms of drift over 200 frames), its phase in ms
constexpr double kClockPeriodWindow = 0.002;
constexpr double kClockPhaseWindowMs = 0.5;

// a measurement and how it is compared with the model
struct FitProblem {
  BenchConfig datasheet;
  MeasuredRecord m;
  double sa = 1, si = 1;   // normalisation: std of the measured angle / current
  BlockSplit split;
  NoiseScale noise;        // white noise of the normalised residual: the loss's unit
  size_t training_rows = 0;   // samples up to the last training one (the training loss needs no more)
};

// the problem for a measurement: the datasheet's step capped at 100 us (the
// scheme's own discretisation error, 0.09 degrees at 500 us, stays below the
// noise), the normalisation and the block split; noise 1 until set
FitProblem make_fit_problem(const BenchConfig& datasheet, MeasuredRecord m);

// the model's response to the measurement's set-points and its residual
struct ModelRun {
  std::vector<BenchSample> sim;
  Residual residual;
};
// (the first `rows` samples only, when fewer: the same values as the whole
// run), asked on the strand `runs`: on a task's of run_paired, stepped
// together with the other task's run; counted in runs.count() (paired_runs.h).
// Every function below that runs the model takes the strand the same way
ModelRun run_model(ModelRuns& runs, const FitProblem& p, const BenchConfig& b, size_t rows = SIZE_MAX);

struct Fit {
  std::vector<int> effects;    // catalogue indices
  std::vector<double> x;       // base factors, then the effects' parameters (param_offset)
  double train = 1e300;        // mean loss on the fitted samples (the objective)
  double sse_train = 0;        // summed loss on the training blocks
  double rho_train = 0;        // lag-1 autocorrelation of the training residual
  double rho_held = 0;         // and of the held-out residual
  double held = 0, white = 0;   // held-out NRMSE, whiteness
  std::vector<double> loss;    // per-sample loss, all samples
  std::vector<std::pair<double, double>> held_ci;   // per x: a held parameter's interval ({0,0}: none)
  int evals = 0;
  bool valid = true;           // false: the effect could not be fitted (e.g. no frame clock found)
};

// the statistics of x on the problem (one model run)
Fit evaluate_fit(ModelRuns& runs, const FitProblem& p, const std::vector<int>& effects, const std::vector<double>& x,
                 Samples set = Samples::training);

// when a fit gives up: after `after` model runs, if its best training loss
// so far is above `loss` (stopped says whether it did)
struct GiveUp {
  int after = 0;
  double loss = 0;
  bool stopped = false;
};

// least squares on `set` from x0 within the bounds; the parameters of a
// frame-clock effect move only within a narrow window around their x0 values
// (kClockPeriodWindow, kClockPhaseWindowMs). With give_up the fit stops
// there with its best point so far if it gives up, and is otherwise the
// same fit as without it
Fit fit_model(ModelRuns& runs, const FitProblem& p, const std::vector<int>& effects, std::vector<double> x0,
              Samples set, int max_eval, GiveUp* give_up = nullptr);

// x with the base factors at the datasheet's (1) and the effects' values kept
std::vector<double> datasheet_start(const std::vector<double>& x);

// the model `cur` refitted from each start (x vectors for cur.effects); the
// best training fit (cur itself if none is better)
Fit refit_from_starts(ModelRuns& runs, const FitProblem& p, const Fit& cur,
                      const std::vector<std::vector<double>>& starts, int max_eval);

// the fit with one more effect on the training blocks, from two starts: the
// reference's base factors and the datasheet's, each with the effect's
// parameters from the best of its starts (a frame clock: fitted to the
// set-point changes' delays, frame_clock.h); the better training fit
// With screen, the first start gives up as fit_model says, and then the
// second start is not run (screen->stopped). A frame clock screens every
// clock that either start finds, each in its own first fit; one that stops
// there is fitted no further, and screen->stopped when all of them stopped. With
// refined (the fit of the form this effect refines, on top of ref), the
// first start is that fit's solution with the extra parameters from the
// catalogue's starts.
Fit fit_with_effect(ModelRuns& runs, const FitProblem& p, const Fit& ref, int effect, GiveUp* screen = nullptr,
                    const Fit* refined = nullptr);

// one start of fit_with_effect for an effect of the smooth kind: 0 from the
// reference's base (or refined's solution), 1 from the datasheet's
Fit fit_effect_start(ModelRuns& runs, const FitProblem& p, const Fit& ref, int effect, int start,
                     GiveUp* screen = nullptr, const Fit* refined = nullptr);

// a model with a frame clock: the clock fitted again on top of the rest of
// the model (its delays measured against a model that now holds the other
// effects found, which biased them while they were missing), the base
// re-fitted with it; f itself when that is not better on the training blocks,
// or when the clock was the last effect found
Fit refit_frame_clock(ModelRuns& runs, const FitProblem& p, const Fit& f);

// the plain frame clock (the catalogue form `plain`, on top of ref) fitted
// from a falling-edge fit's solution: the slope dropped, the phase moved to
// the latch of the mean set-point's pulse (the inverse of the falling-edge
// fit's first start), scanned and fitted as the clock's fit does. Where the
// plain clock's own fit stopped at a compromise the falling-edge fit, with
// its own clocks, got past, the richer form would otherwise be credited
// with what the optimiser missed (effect_search.h, fit_refining_forms)
Fit refit_plain_clock(ModelRuns& runs, const FitProblem& p, const Fit& ref, int plain, const Fit& falling);

// 95 % intervals of f.x on all data (finite-difference Jacobian of the free
// parameters; residual_stats.h confidence_intervals); held ones from f.held_ci
std::vector<std::pair<double, double>> fit_intervals(ModelRuns& runs, const FitProblem& p, const Fit& f);

}  // namespace chainsim
