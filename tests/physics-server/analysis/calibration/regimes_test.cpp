// Regimes of a measurement whose motion is known: a servo that moves at a
// constant 500 deg/s towards each set-point.
#include "analysis/calibration/regimes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace chainsim {
namespace {

// 30 -> 120 at 0.1 s (arrives at 0.28 s), 120 -> 60 at 0.6 s (arrives at
// 0.72 s); 1 ms samples; current 0.4 A from 0.14 to 0.2 s when with_current
MeasuredRecord record(bool with_current) {
  MeasuredRecord m;
  m.has_current = with_current;
  double angle = 30;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * 1e-3;
    const double sp = t < 0.1 - 1e-9 ? 30 : t < 0.6 - 1e-9 ? 120 : 60;
    m.t.push_back(t);
    m.sp.push_back(sp);
    m.angle.push_back(angle);
    m.current.push_back(with_current && t > 0.14 && t < 0.2 ? 0.4 : 0.01);
    const double step = 0.5;  // deg per ms
    angle += std::clamp(sp - angle, -step, step);
  }
  return m;
}

int at(const std::vector<int>& reg, double t) { return reg[static_cast<size_t>(std::lround(t * 1000))]; }

TEST(Regimes, EachPhaseOfAMoveGetsItsRegime) {
  const std::vector<int> reg = classify_regimes(record(false), 0.42);
  EXPECT_EQ(at(reg, 0.05), kHold);
  EXPECT_EQ(at(reg, 0.12), kStepOnset);   // within 40 ms of the set-point change
  EXPECT_EQ(at(reg, 0.20), kSlewing);     // fast, far from the set-point
  EXPECT_EQ(at(reg, 0.26), kBraking);     // fast, within 20 degrees of it
  EXPECT_EQ(at(reg, 0.40), kHold);
  EXPECT_EQ(at(reg, 0.62), kReversal);    // the set-point changed direction
  EXPECT_EQ(at(reg, 0.66), kSlewing);
  EXPECT_EQ(at(reg, 0.90), kHold);
  EXPECT_EQ(regime_names()[kBraking], "braking");
}

TEST(Regimes, HighCurrentComesBeforeTheMotionRegimes) {
  const std::vector<int> reg = classify_regimes(record(true), 0.42);
  EXPECT_EQ(at(reg, 0.12), kStepOnset);     // the onset window first
  EXPECT_EQ(at(reg, 0.17), kHighCurrent);   // 0.4 A > 60 % of 0.42 A
  EXPECT_EQ(at(reg, 0.22), kSlewing);
  // with a larger stall current 0.4 A is not high
  EXPECT_EQ(at(classify_regimes(record(true), 1.0), 0.17), kSlewing);
}

TEST(Regimes, RunsAreContiguousStretchesOfOneRegime) {
  const std::vector<RegimeRun> runs = regime_runs({kHold, kHold, kStepOnset, kStepOnset, kStepOnset, kHold});
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[1].first, 2u);
  EXPECT_EQ(runs[1].last, 4u);
  EXPECT_EQ(runs[1].regime, kStepOnset);
  EXPECT_EQ(runs[2].first, 5u);
  EXPECT_TRUE(regime_runs({}).empty());
}

TEST(Regimes, SignatureIsTheResidualsConcentration) {
  // 10 samples, 2 of them braking, all the residual there
  const std::vector<int> reg = {kHold, kHold, kBraking, kBraking, kHold, kHold, kHold, kHold, kHold, kHold};
  Residual r;
  r.angle = {0, 0, 1, 1, 0, 0, 0, 0, 0, 0};
  r.current.assign(10, 0.0);
  EXPECT_DOUBLE_EQ(regime_signature(r, reg, {"braking"}), 5.0);   // all of it in 20 % of the time
  EXPECT_DOUBLE_EQ(regime_signature(r, reg, {"hold"}), 0.0);
  EXPECT_DOUBLE_EQ(regime_signature(r, reg, {"braking", "hold"}), 1.0);
  EXPECT_DOUBLE_EQ(regime_signature(r, reg, {"reversal"}), 0.0);  // no such samples
}

}  // namespace
}  // namespace chainsim
