// The calibration's acceptance tests on inputs whose answer is known: the
// quantiles, the profile-likelihood gate (the interval excludes the null),
// and the held-out likelihood ratio: a real improvement passes, one confined
// to a few events passes, a parameter fitted to the noise of the training
// blocks passes about as rarely as its level says, a worse candidate never.
#include "analysis/calibration/selection_rule.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace chainsim {
namespace {

constexpr size_t kN = 4000;

BlockSplit split() {
  std::vector<double> t(kN);
  for (size_t k = 0; k < kN; ++k) t[k] = k * 1e-3;
  return split_blocks(t);
}

std::vector<double> noise_loss(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> d(0, 1);
  std::vector<double> v(kN);
  for (double& x : v) {
    const double a = d(rng);
    x = a * a;
  }
  return v;
}

TEST(SelectionRule, Quantiles) {
  EXPECT_NEAR(normal_upper_quantile(0.05), 1.6449, 1e-3);
  EXPECT_NEAR(normal_upper_quantile(0.025), 1.9600, 1e-3);
  EXPECT_NEAR(student_t_upper_quantile(0.025, 10), 2.228, 0.01);
  EXPECT_NEAR(student_t_upper_quantile(0.05, 19), 1.729, 0.005);
  EXPECT_NEAR(student_t_upper_quantile(0.005, 19), 2.861, 0.02);
  EXPECT_DOUBLE_EQ(chi_square_95(1), 3.841);
  EXPECT_DOUBLE_EQ(chi_square_95(2), 5.991);
  EXPECT_NEAR(chi_square_upper_quantile(0.05, 1), 3.841, 0.15);
  EXPECT_NEAR(chi_square_upper_quantile(0.05, 2), 5.991, 0.1);
  EXPECT_NEAR(chi_square_upper_quantile(0.05 / 9, 1), 7.69, 0.3);   // Bonferroni over 9
  // the screen: the chi-square medians, 0.455 and 1.386
  EXPECT_NEAR(screen_crit(1), 0.455, 0.03);
  EXPECT_NEAR(screen_crit(2), 1.386, 0.05);
}

// the summed loss at which the profiled ratio reaches a value, on both
// sides of the white floor (sse = terms) and where nothing reaches it
TEST(SelectionRule, ProfiledSseAtInvertsTheProfiledRatio) {
  for (double sse_ref : {900.0, 1000.0, 1300.0, 40000.0})
    for (double lr : {0.455, 3.84, 50.0}) {
      const double sse = profiled_sse_at(sse_ref, lr, 1000.0);
      EXPECT_LT(sse, sse_ref);
      EXPECT_NEAR(profiled_lr(sse_ref, sse, 1000.0), lr, 1e-9 * sse_ref) << sse_ref << " " << lr;
    }
  EXPECT_EQ(profiled_sse_at(10.0, 50.0, 1000.0), 0.0);
  EXPECT_EQ(profiled_sse_at(10.0, 1.0, 0.0), 0.0);
}

TEST(SelectionRule, TheProfileIntervalExcludesTheNullOnlyForAClearDrop) {
  // white residual: the statistic is the drop of the summed loss
  ProfileTest t = profile_test(1000.0, 990.0, 1000.0, 0.0, 1);
  EXPECT_DOUBLE_EQ(t.stat, 10.0);
  EXPECT_TRUE(t.excludes_null);
  EXPECT_FALSE(profile_test(1000.0, 997.0, 1000.0, 0.0, 1).excludes_null);   // 3 < 3.84
  // two parameters need more
  EXPECT_FALSE(profile_test(1000.0, 995.0, 1000.0, 0.0, 2).excludes_null);   // 5 < 5.99
  // a correlated residual (rho 0.5: 3x fewer independent samples) divides it
  t = profile_test(1000.0, 990.0, 1000.0, 0.5, 1);
  EXPECT_DOUBLE_EQ(t.inflation, 3.0);
  EXPECT_NEAR(t.stat, 10.0 / 3.0, 1e-12);
  EXPECT_FALSE(t.excludes_null);
  // a candidate worse than its reference
  EXPECT_FALSE(profile_test(1000.0, 1010.0, 1000.0, 0.0, 1).excludes_null);
  // a misfit of 10 noise variances per sample that no model has: trimming
  // 0.3 % off it is not the 30 noise variances the fixed unit counted
  t = profile_test(10000.0, 9970.0, 1000.0, 0.0, 1);
  EXPECT_NEAR(t.stat, 1000.0 * std::log(10.0 / 9.97), 1e-9);
  EXPECT_FALSE(t.excludes_null);
  // a candidate that brings it down to the noise: n log of the variance ratio
  t = profile_test(10000.0, 1000.0, 1000.0, 0.0, 1);
  EXPECT_NEAR(t.stat, 1000.0 * std::log(10.0), 1e-9);
  EXPECT_TRUE(t.excludes_null);
}

TEST(SelectionRule, HeldOutTestPassesARealGainAndNotNoise) {
  const BlockSplit s = split();
  ASSERT_EQ(s.batch.size(), kN);
  // a candidate whose loss is 20 % lower everywhere
  std::vector<double> ref = noise_loss(1), cand = ref;
  for (double& x : cand) x *= 0.8;
  HeldOutTest t = held_out_test(ref, cand, 0.0, s, 1, 9, 1);
  EXPECT_TRUE(t.significant) << t.stat;
  EXPECT_NEAR(t.crit, chi_square_upper_quantile(0.05 / 9, 1), 1e-12);
  // a correlated residual divides the statistic by (1 + rho) / (1 - rho)
  const HeldOutTest tc = held_out_test(ref, cand, 0.5, s, 1, 9, 1);
  EXPECT_NEAR(tc.stat, t.stat / 3.0, 1e-9);
  // a gain at a few events only (one sample in 100 drops by 50), all of it
  // in the first held-out block
  cand = ref;
  for (size_t k = 550; k < 1000; k += 100) cand[k] = ref[k] - 50;
  t = held_out_test(ref, cand, 0.0, s, 1, 9, 1);
  std::printf("gain at 5 events of one block: LR %.1f (crit %.2f)\n", t.stat, t.crit);
  EXPECT_TRUE(t.significant);
  // the same held-out samples the other way round: worse, never accepted
  EXPECT_FALSE(held_out_test(cand, ref, 0.0, s, 1, 9, 1).significant);
  // a parameter fitted to the noise: the residual r (unit white noise) minus
  // a slow basis function scaled to fit r on the training blocks; on the
  // held-out blocks it passes at about the test's level or below
  auto trial = [&](unsigned seed, int comparisons) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> d(0, 1);
    std::vector<double> r(kN), g(kN);
    const double f = 0.5 + 3.0 * (seed % 7);   // cycles over the record
    for (size_t k = 0; k < kN; ++k) r[k] = d(rng), g[k] = std::sin(2 * 3.14159265358979 * f * k / kN + seed);
    double num = 0, den = 0;
    for (size_t k = 0; k < kN; ++k)
      if (s.in(k, Samples::training)) num += r[k] * g[k], den += g[k] * g[k];
    const double a = num / den;
    std::vector<double> lr(kN), lc(kN);
    for (size_t k = 0; k < kN; ++k) lr[k] = r[k] * r[k], lc[k] = (r[k] - a * g[k]) * (r[k] - a * g[k]);
    return held_out_test(lr, lc, 0.0, s, 1, comparisons, 1).significant;
  };
  int passed = 0;
  const int trials = 400;
  for (int i = 0; i < trials; ++i) passed += trial(100 + i, 1);
  std::printf("fitted to noise: %d of %d significant at 5 %%\n", passed, trials);
  EXPECT_LT(passed, trials * 0.07);
  passed = 0;
  for (int i = 0; i < trials; ++i) passed += trial(100 + i, 9);
  EXPECT_LT(passed, trials * 0.015);
}

}  // namespace
}  // namespace chainsim
