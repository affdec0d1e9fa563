// The calibration's statistics on inputs whose answer is known: white noise
// against a slow sine (whiteness, structured gap), the block split, NRMSE
// with two channels and a mask, and the intervals' inflation by the
// residual's correlation.
#include "analysis/calibration/residual_stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace chainsim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kN = 4000;

std::vector<double> times() {
  std::vector<double> t(kN);
  for (size_t k = 0; k < kN; ++k) t[k] = k * 1e-3;
  return t;
}

Residual angle_only(std::vector<double> v) {
  Residual r;
  r.angle = std::move(v);
  r.current.assign(r.angle.size(), 0.0);
  return r;
}

std::vector<double> white(double sd, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> d(0, sd);
  std::vector<double> v(kN);
  for (double& x : v) x = d(rng);
  return v;
}

std::vector<double> sine(double amp, double hz) {
  std::vector<double> v(kN);
  for (size_t k = 0; k < kN; ++k) v[k] = amp * std::sin(2 * kPi * hz * k * 1e-3);
  return v;
}

TEST(ResidualStats, BlocksAreEqualSpansOfTimeAlternatingTrainingAndHeldOut) {
  const BlockSplit s = split_blocks(times());
  ASSERT_EQ(s.block.size(), kN);
  EXPECT_EQ(s.block.front(), 0);
  EXPECT_EQ(s.block.back(), kCvBlocks - 1);
  for (int b = 0; b < kCvBlocks; ++b)
    EXPECT_NEAR(std::count(s.block.begin(), s.block.end(), b), double(kN) / kCvBlocks, 2) << b;
  EXPECT_EQ(s.block[499], 0);
  EXPECT_EQ(s.block[500], 1);
  EXPECT_TRUE(s.in(0, Samples::training));
  EXPECT_FALSE(s.in(0, Samples::held_out));
  EXPECT_TRUE(s.in(500, Samples::held_out));
  EXPECT_TRUE(s.in(500, Samples::all));
}

TEST(ResidualStats, WhiteNoiseIsWhiteASlowSineIsNot) {
  const BlockSplit s = split_blocks(times());
  const double w_noise = whiteness(angle_only(white(1.0, 1)), s, Samples::held_out);
  const double w_sine = whiteness(angle_only(sine(1.0, 2.0)), s, Samples::held_out);
  std::printf("whiteness: white noise %.3f, 2 Hz sine %.1f\n", w_noise, w_sine);
  EXPECT_NEAR(w_noise, 1.0, 0.1);
  EXPECT_GT(w_sine, 20.0);
  // a structured current channel makes the residual structured
  Residual r = angle_only(white(1.0, 2));
  r.has_current = true;
  r.current = sine(1.0, 2.0);
  EXPECT_GT(whiteness(r, s, Samples::held_out), 20.0);
}

TEST(ResidualStats, TheGapIsTheStructuredPartAlone) {
  const BlockSplit s = split_blocks(times());
  const double gap_noise = structured_error(angle_only(white(0.5, 3)), s, Samples::held_out);
  std::vector<double> v = sine(1.0, 2.0);
  const std::vector<double> n = white(0.5, 4);
  for (size_t k = 0; k < kN; ++k) v[k] += n[k];
  const Residual mixed = angle_only(v);
  const double gap = structured_error(mixed, s, Samples::held_out);
  const double plain = nrmse(mixed, s, Samples::held_out);
  std::printf("gap: noise alone %.4f; sine (rms %.3f) + noise %.4f, plain NRMSE %.4f\n", gap_noise,
              1 / std::sqrt(2.0), gap, plain);
  EXPECT_LT(gap_noise, 0.05);
  EXPECT_NEAR(gap, 1 / std::sqrt(2.0), 0.05);
  EXPECT_NEAR(plain, std::sqrt(0.5 + 0.25), 0.05);  // the noise counts in the plain error
  Residual bad = mixed;
  bad.finite = false;
  EXPECT_EQ(structured_error(bad, s, Samples::held_out), 1e6);
  EXPECT_EQ(nrmse(bad, s, Samples::held_out), 1e6);
}

// a misfit that changes from one sample to the next (a 250 Hz sine sampled
// at 1 kHz: 0, a, 0, -a) has first differences as large as itself, so a
// residual's own white level counts all of it as noise; against the white
// level of a model without it (the smaller of the two) it is all gap
TEST(ResidualStats, TwoModelsGapsShareOneWhiteLevel) {
  const BlockSplit s = split_blocks(times());
  std::vector<double> v = sine(1.0, 250.0);
  const std::vector<double> n = white(0.5, 5);
  for (size_t k = 0; k < kN; ++k) v[k] += n[k];
  const Residual fast = angle_only(v), noise = angle_only(white(0.5, 6));
  const double alone = structured_error(fast, s, Samples::held_out);
  const auto [with_misfit, without] = structured_errors(fast, noise, s, Samples::held_out);
  std::printf("250 Hz misfit (rms %.3f) + noise: gap alone %.4f, against the other model's white level %.4f; "
              "noise alone %.4f\n", 1 / std::sqrt(2.0), alone, with_misfit, without);
  EXPECT_LT(alone, 0.1);
  EXPECT_NEAR(with_misfit, 1 / std::sqrt(2.0), 0.05);
  EXPECT_LT(without, 0.1);   // the noise level's own sampling error: sqrt(0.25 x 0.02)
  // the order of the two does not matter; one model twice is its own gap
  const auto [b, a] = structured_errors(noise, fast, s, Samples::held_out);
  EXPECT_EQ(a, with_misfit);
  EXPECT_EQ(b, without);
  const auto [same, same2] = structured_errors(fast, fast, s, Samples::held_out);
  EXPECT_EQ(same, alone);
  EXPECT_EQ(same2, alone);
  // a non-finite model: its gap is 1e6 and the other keeps its own level
  Residual bad = noise;
  bad.finite = false;
  const auto [g_bad, g_fast] = structured_errors(bad, fast, s, Samples::held_out);
  EXPECT_EQ(g_bad, 1e6);
  EXPECT_EQ(g_fast, alone);
}

TEST(ResidualStats, NrmseAveragesTheChannelsAndHonoursTheMask) {
  const BlockSplit s = split_blocks(times());
  Residual r = angle_only(std::vector<double>(kN, 3.0));
  EXPECT_DOUBLE_EQ(nrmse(r, s, Samples::all), 3.0);
  r.has_current = true;
  r.current.assign(kN, 4.0);
  EXPECT_DOUBLE_EQ(nrmse(r, s, Samples::all), std::sqrt((9.0 + 16.0) / 2));
  std::vector<bool> mask(kN, false);
  r.angle[10] = 1.0, r.current[10] = 1.0;
  mask[10] = true;
  EXPECT_DOUBLE_EQ(nrmse(r, s, Samples::all, &mask), 1.0);
  EXPECT_EQ(nrmse(r, s, Samples::held_out, &mask), 0.0);  // sample 10 is in a training block
  EXPECT_DOUBLE_EQ(stdev({1, 2, 3, 4}), std::sqrt(1.25));
}

// a straight line fitted to noise: J = [1, t]; the intervals contain the
// truth, and a correlated residual of the same size widens them by
// sqrt((1 + rho) / (1 - rho))
TEST(ResidualStats, IntervalsWidenWithTheResidualsCorrelation) {
  const size_t m = kN;
  Eigen::MatrixXd J(m, 2);
  for (size_t k = 0; k < m; ++k) J(k, 0) = 1, J(k, 1) = k * 1e-3;
  const std::vector<double> x = {0.0, 0.0};
  Eigen::VectorXd rw(m), rc(m);
  const std::vector<double> n = white(1.0, 5);
  const double rho = 0.8;
  double prev = 0;
  for (size_t k = 0; k < m; ++k) {
    rw(k) = n[k];
    prev = rho * prev + std::sqrt(1 - rho * rho) * n[k];  // AR(1), unit variance
    rc(k) = prev;
  }
  rc *= rw.norm() / rc.norm();  // the same size: only the correlation differs
  const auto ciw = confidence_intervals(J, rw, m, x, 2);
  const auto cic = confidence_intervals(J, rc, m, x, 2);
  const double ww = ciw[1].second - ciw[1].first, wc = cic[1].second - cic[1].first;
  // the slope's standard error for white noise: sd / sqrt(sum (t - mean)^2)
  const double se = 1.0 / std::sqrt(m * (m * m - 1) / 12.0 * 1e-6);
  std::printf("interval widths: white %.4f (expected %.4f), AR(1) rho 0.8 %.4f, ratio %.3f (expected %.3f)\n", ww,
              2 * 1.96 * se, wc, wc / ww, std::sqrt((1 + rho) / (1 - rho)));
  EXPECT_NEAR(ww, 2 * 1.96 * se, 0.1 * ww);
  EXPECT_LT(ciw[1].first, 0.0);
  EXPECT_GT(ciw[1].second, 0.0);
  EXPECT_NEAR(wc / ww, std::sqrt((1 + rho) / (1 - rho)), 0.15 * std::sqrt((1 + rho) / (1 - rho)));
  // parameters from first_nonnegative on are floored at 0
  const auto cin = confidence_intervals(J, rw, m, x, 1);
  EXPECT_LT(cin[0].first, 0.0);
  EXPECT_EQ(cin[1].first, 0.0);
}

}  // namespace
}  // namespace chainsim
