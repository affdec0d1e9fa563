// The greedy search's resolution test (effect_search.h): the change an
// effect makes where it acts, as its 99th percentile over those samples.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "analysis/calibration/effect_search.h"

namespace chainsim {
namespace {

// a current limit that cuts the fastest moves by 2 noise units on 5 of its
// 205 samples and leaves the rest at half a unit: resolved, though the rms
// of its change (0.58) is below one unit
TEST(EffectResolution, AnEffectActingHardOnAFewSamplesIsResolved) {
  std::vector<double> change(200, 0.5);
  change.insert(change.begin() + 17, 5, 2.0);
  double ss = 0;
  for (double c : change) ss += c * c;
  EXPECT_LT(std::sqrt(ss / static_cast<double>(change.size())), kMinResolution);
  EXPECT_DOUBLE_EQ(resolved_change(change), 2.0);
  EXPECT_GE(resolved_change(change), kMinResolution);
}

// one sample at a step's edge is not enough, and a change under the noise
// everywhere is not resolved however many samples it has
TEST(EffectResolution, OneSampleOrASubNoiseChangeIsNot) {
  std::vector<double> edge(200, 0.5);
  edge[100] = 5.0;
  EXPECT_DOUBLE_EQ(resolved_change(edge), 0.5);
  const std::vector<double> everywhere(5000, 0.9);
  EXPECT_LT(resolved_change(everywhere), kMinResolution);
  EXPECT_EQ(resolved_change({}), 0.0);
}

}  // namespace
}  // namespace chainsim
