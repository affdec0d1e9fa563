// The calibration's least-squares fit (servo_fit.h) on records of the bench
// model itself with known base factors: it finds them, keeps to its bounds
// and to its budget of model runs, and never ends worse than it started.
#include "analysis/calibration/servo_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "analysis/calibration/effect_catalogue.h"
#include "bench_record.h"

namespace chainsim {
namespace {

FitProblem problem_for(const std::vector<double>& truth) {
  ModelRuns runs;
  const BenchConfig ds = test_datasheet();
  FitProblem p = make_fit_problem(ds, bench_record(model_config(ds, {}, truth), 7));
  // the loss's unit: the white noise the true model leaves
  p.noise = white_noise_scale(run_model(runs, p, model_config(ds, {}, truth)).residual, p.split);
  return p;
}

TEST(FitModel, FindsTheBaseFactorsOfAModelRecord) {
  ModelRuns runs;
  const std::vector<double> truth = {1.25, 0.85, 1.15, 1.3};
  const FitProblem p = problem_for(truth);
  const Fit start = evaluate_fit(runs, p, {}, std::vector<double>(kNumBase, 1.0));
  const Fit f = fit_model(runs, p, {}, std::vector<double>(kNumBase, 1.0), Samples::training, kMaxEvalBase);
  std::printf("loss %.3f -> %.3f in %d model runs; factors", start.train, f.train, f.evals);
  for (double x : f.x) std::printf(" %.4f", x);
  std::printf(" (true 1.25 0.85 1.15 1.3)\n");
  for (int i = 0; i < kNumBase; ++i) EXPECT_NEAR(f.x[i], truth[i], 0.03 * truth[i]) << kBaseNames[i];
  // at the truth the loss is the noise alone: one unit a channel, two channels
  EXPECT_LT(f.train, 2.1);
  EXPECT_GT(start.train, 10 * f.train);
  EXPECT_LE(f.evals, kMaxEvalBase);
}

TEST(FitModel, KeepsToItsBoundsAndItsBudget) {
  ModelRuns runs;
  // a gain above the factors' range: the fit ends on the bound, not beyond
  const FitProblem p = problem_for({2.0, 1.0, 1.0, 1.0});
  const Fit f = fit_model(runs, p, {}, std::vector<double>(kNumBase, 1.0), Samples::training, kMaxEvalBase);
  EXPECT_LE(f.x[0], kBaseFactorHi);
  EXPECT_GT(f.x[0], kBaseFactorHi - 0.05);
  // a budget smaller than one Jacobian and step: no more runs than that, and
  // the loss no higher than at the start
  const Fit start = evaluate_fit(runs, p, {}, std::vector<double>(kNumBase, 1.0));
  for (int budget : {1, 3, 12}) {
    const Fit g = fit_model(runs, p, {}, std::vector<double>(kNumBase, 1.0), Samples::training, budget);
    EXPECT_LE(g.evals, budget);
    EXPECT_LE(g.train, start.train) << budget;
  }
}

// a record with base factors off the datasheet and, when `deadband` > 0, a
// deadband of that many degrees; the loss's unit from the true model
FitProblem deadband_problem(double deadband, unsigned seed) {
  ModelRuns runs;
  const BenchConfig ds = test_datasheet();
  const int db = effect_variants("deadband").front();
  std::vector<double> truth = {1.1, 0.9, 1.05, 1.0};
  truth.push_back(deadband);
  FitProblem p = make_fit_problem(ds, bench_record(model_config(ds, {db}, truth), seed));
  p.noise = white_noise_scale(run_model(runs, p, model_config(ds, {db}, truth)).residual, p.split);
  return p;
}

TEST(FitModel, GivesUpOnlyWhereItShowsNoGain) {
  ModelRuns runs;
  const int db = effect_variants("deadband").front();
  const std::vector<double> base = {1.1, 0.9, 1.05, 1.0};
  std::vector<double> x0 = base;
  x0.push_back(0.0);
  // a 2 degree deadband in the record: after 11 runs far below the
  // reference's loss, so the fit goes on, the same fit as without the screen
  {
    const FitProblem p = deadband_problem(2.0, 11);
    const Fit ref = evaluate_fit(runs, p, {}, base);
    GiveUp g{11, 0.99 * ref.train};
    const Fit screened = fit_model(runs, p, {db}, x0, Samples::training, kMaxEvalJoint, &g);
    const Fit plain = fit_model(runs, p, {db}, x0, Samples::training, kMaxEvalJoint);
    std::printf("deadband 2 deg: loss %.3f -> %.3f, %.3f deg in %d model runs\n", ref.train, screened.train,
                screened.x[kNumBase], screened.evals);
    EXPECT_FALSE(g.stopped);
    EXPECT_EQ(screened.x, plain.x);
    EXPECT_EQ(screened.evals, plain.evals);
    EXPECT_NEAR(screened.x[kNumBase], 2.0, 0.1);
  }
  // no deadband: the reference's loss is not beaten by 1 % within 11 runs,
  // the fit stops there with its best point so far
  {
    const FitProblem p = deadband_problem(0.0, 12);
    const Fit ref = evaluate_fit(runs, p, {}, base);
    GiveUp g{11, 0.99 * ref.train};
    const Fit f = fit_model(runs, p, {db}, x0, Samples::training, kMaxEvalJoint, &g);
    std::printf("no deadband: stopped %d after %d model runs, loss %.4f -> %.4f, %.4f deg\n", g.stopped, f.evals,
                ref.train, f.train, f.x[kNumBase]);
    EXPECT_TRUE(g.stopped);
    EXPECT_EQ(f.evals, 11);
    EXPECT_LE(f.train, ref.train * (1 + 1e-12));
    EXPECT_GT(f.train, 0.99 * ref.train);
  }
}

// a form that refines another starts from that form's solution, with its
// extra parameter from the catalogue's starts; a screen that gives up at
// once leaves it there, and the second start is not run
TEST(FitModel, ARefiningFormStartsFromTheFormItRefines) {
  ModelRuns runs;
  const FitProblem p = deadband_problem(0.0, 13);
  const int bridge = effect_variants("supply_sag")[0];
  const int rail = effect_variants("supply_sag")[2];
  ASSERT_STREQ(effect_catalogue()[rail].refines, effect_catalogue()[bridge].variant);
  const Fit ref = evaluate_fit(runs, p, {}, {1.1, 0.9, 1.05, 1.0});
  const Fit refined = fit_with_effect(runs, p, ref, bridge);
  GiveUp g{1, 0.0};
  const Fit f = fit_with_effect(runs, p, ref, rail, &g, &refined);
  EXPECT_TRUE(g.stopped);
  EXPECT_EQ(f.evals, 1);
  ASSERT_EQ(f.x.size(), refined.x.size() + 1);
  // (through the optimiser's unit scaling and back: equal to rounding)
  for (size_t i = 0; i < refined.x.size(); ++i) EXPECT_NEAR(f.x[i], refined.x[i], 1e-9 * refined.x[i]) << i;
  bool from_starts = false;
  for (const std::vector<double>& tail : effect_catalogue()[rail].starts)
    from_starts |= std::fabs(f.x.back() - tail.back()) < 1e-9 * tail.back();
  EXPECT_TRUE(from_starts) << f.x.back();
}

}  // namespace
}  // namespace chainsim
