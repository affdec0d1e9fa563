// The calibration's acceptance tests on inputs whose answer is known: the
// quantiles, the profile-likelihood gate (the interval excludes the null),
// and the held-out test: a real improvement passes, one confined to a few
// events passes, noise passes about as often as its level says, a worse
// candidate never.
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
}

TEST(SelectionRule, TheProfileIntervalExcludesTheNullOnlyForAClearDrop) {
  // white residual: the statistic is the drop of the summed loss
  ProfileTest t = profile_test(1000.0, 990.0, 0.0, 1);
  EXPECT_DOUBLE_EQ(t.stat, 10.0);
  EXPECT_TRUE(t.excludes_null);
  EXPECT_FALSE(profile_test(1000.0, 997.0, 0.0, 1).excludes_null);   // 3 < 3.84
  // two parameters need more
  EXPECT_FALSE(profile_test(1000.0, 995.0, 0.0, 2).excludes_null);   // 5 < 5.99
  // a correlated residual (rho 0.5: 3x fewer independent samples) divides it
  t = profile_test(1000.0, 990.0, 0.5, 1);
  EXPECT_DOUBLE_EQ(t.inflation, 3.0);
  EXPECT_NEAR(t.stat, 10.0 / 3.0, 1e-12);
  EXPECT_FALSE(t.excludes_null);
  // a candidate worse than its reference
  EXPECT_FALSE(profile_test(1000.0, 1010.0, 0.0, 1).excludes_null);
}

TEST(SelectionRule, HeldOutTestPassesARealGainAndNotNoise) {
  const BlockSplit s = split();
  ASSERT_EQ(s.batch.size(), kN);
  EXPECT_EQ(s.batch[0], 0);
  EXPECT_EQ(s.batch[499], kBatchesPerBlock - 1);
  // a candidate whose loss is 20 % lower everywhere
  std::vector<double> ref = noise_loss(1), cand = ref;
  for (double& x : cand) x *= 0.8;
  HeldOutTest t = held_out_test(ref, cand, s, 9);
  EXPECT_EQ(t.batches, kCvBlocks / 2 * kBatchesPerBlock);
  EXPECT_TRUE(t.significant) << t.t;
  EXPECT_NEAR(t.crit, student_t_upper_quantile(0.05 / 9, t.batches - 1), 1e-12);
  // a gain at a few events only (one sample in 100 drops by 50)
  cand = ref;
  for (size_t k = 50; k < kN; k += 100) cand[k] = ref[k] - 50;
  t = held_out_test(ref, cand, s, 9);
  std::printf("gain at 40 events: t %.2f (crit %.2f)\n", t.t, t.crit);
  EXPECT_TRUE(t.significant);
  // the same held-out samples the other way round: worse, never accepted
  EXPECT_FALSE(held_out_test(cand, ref, s, 9).significant);
  // noise against noise: significant at about the test's level
  int passed = 0;
  const int trials = 400;
  for (int i = 0; i < trials; ++i)
    passed += held_out_test(noise_loss(100 + i), noise_loss(10000 + i), s, 1).significant;
  std::printf("noise vs noise: %d of %d significant at 5 %%\n", passed, trials);
  EXPECT_LT(passed, trials * 0.09);
  EXPECT_GT(passed, trials * 0.02);
  // with 9 comparisons (Bonferroni) far fewer
  passed = 0;
  for (int i = 0; i < trials; ++i)
    passed += held_out_test(noise_loss(100 + i), noise_loss(10000 + i), s, 9).significant;
  EXPECT_LT(passed, trials * 0.02);
}

}  // namespace
}  // namespace chainsim
