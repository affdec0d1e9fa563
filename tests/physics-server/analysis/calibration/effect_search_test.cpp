// The greedy search's resolution test (effect_search.h): the change an
// effect makes where it acts, as its 99th percentile over those samples; and
// the screen of a candidate's fit, the loss it must reach and when; which
// candidates are fitted from the datasheet start too.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "analysis/calibration/effect_catalogue.h"
#include "analysis/calibration/effect_search.h"
#include "analysis/calibration/selection_rule.h"

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

// the screen's threshold: at its loss the profile statistic against the
// reference is the chi-square median, with the reference's inflation; it is
// checked after twice BOBYQA's interpolation set
TEST(Screen, StopsAtTheLossOfTheChiSquareMedian) {
  ModelRuns runs;
  FitProblem p;
  p.m.has_current = true;
  for (int k = 0; k < 800; ++k) p.m.t.push_back(k * 5e-3);
  p.split = split_blocks(p.m.t);
  double samples = 0;
  for (size_t k = 0; k < p.split.block.size(); ++k) samples += p.split.in(k, Samples::training);
  const int deadband = effect_variants("deadband").front();
  const int compliant = effect_variants("backlash").back();
  for (double sse_per_term : {1.0, 1.3, 40.0}) {
    Fit ref;
    ref.sse_train = sse_per_term * 2 * samples;
    ref.rho_train = 0.3;
    const double inflation = 1.3 / 0.7;
    const GiveUp one = screen_for(p, ref, deadband);
    EXPECT_EQ(one.after, 2 * (2 * (kNumBase + 1) + 1));
    EXPECT_NEAR(profiled_lr(ref.sse_train, one.loss * samples, 2 * samples) / inflation, screen_crit(1), 1e-6);
    EXPECT_LT(one.loss * samples, ref.sse_train);
    EXPECT_FALSE(one.stopped);
    // a two-parameter form on top of an accepted effect: more runs, a lower loss
    ref.effects = {deadband};
    const GiveUp two = screen_for(p, ref, compliant);
    EXPECT_EQ(two.after, 2 * (2 * (kNumBase + 3) + 1));
    EXPECT_NEAR(profiled_lr(ref.sse_train, two.loss * samples, 2 * samples) / inflation, screen_crit(2), 1e-6);
    EXPECT_LT(two.loss, one.loss);
    // a refining form against the form it refines, where that form
    // predicts the held-out blocks better than the reference: its one
    // extra parameter
    Fit bridge;
    bridge.effects = {effect_variants("supply_sag")[0]};
    bridge.sse_train = 0.8 * ref.sse_train;
    bridge.rho_train = 0.1;
    ref.effects = {};
    ref.loss.assign(p.m.t.size(), 2.0 * sse_per_term);
    bridge.loss.assign(p.m.t.size(), 2.0 * 0.8 * sse_per_term);
    const int rail_form = effect_variants("supply_sag")[2];
    const GiveUp rail = screen_for(p, ref, rail_form, &bridge);
    EXPECT_EQ(rail.after, 2 * (2 * (kNumBase + 2) + 1));
    EXPECT_NEAR(profiled_lr(bridge.sse_train, rail.loss * samples, 2 * samples) / (1.1 / 0.9), screen_crit(1), 1e-6);
    // where it does not (no better on the held-out blocks), or was not
    // fitted, the refining form is screened against the reference with all
    // its parameters, as the search may name it without beating that form
    const GiveUp alone = screen_for(p, ref, rail_form);
    bridge.loss = ref.loss;
    const GiveUp no_better = screen_for(p, ref, rail_form, &bridge);
    EXPECT_DOUBLE_EQ(no_better.loss, alone.loss);
    EXPECT_GT(no_better.loss, rail.loss);
    bridge.loss.assign(p.m.t.size(), 2.0 * 0.8 * sse_per_term);
    bridge.valid = false;
    EXPECT_DOUBLE_EQ(screen_for(p, ref, rail_form, &bridge).loss, alone.loss);
  }
}

// the datasheet start is run for an effect whose best first start gained at
// least a quarter of the round's best first start, and for every candidate
// when no first start gained on the held-out blocks
// a refining form refines a form of its own effect that refines nothing (the
// search decides which refining forms to fit before fitting any of them)
TEST(Catalogue, ARefiningFormRefinesAFormThatRefinesNothing) {
  int refining = 0;
  for (const Effect& ef : effect_catalogue()) {
    if (!*ef.refines) continue;
    ++refining;
    int found = 0;
    for (const Effect& s : effect_catalogue())
      if (std::string(s.name) == ef.name && std::string(s.variant) == ef.refines) {
        ++found;
        EXPECT_STREQ(s.refines, "") << ef.name << " " << ef.variant << " refines " << ef.refines;
        EXPECT_EQ(s.params.size() + 1, ef.params.size()) << ef.variant;
      }
    EXPECT_EQ(found, 1) << ef.name << " " << ef.variant;
  }
  EXPECT_GE(refining, 2);
}

TEST(SecondStart, OnlyForAnEffectNearTheRoundsBestFirstStart) {
  EXPECT_TRUE(run_second_start(1.0, 1.0));
  EXPECT_TRUE(run_second_start(0.25, 1.0));
  EXPECT_FALSE(run_second_start(0.2499, 1.0));
  EXPECT_FALSE(run_second_start(-3.0, 1.0));
  EXPECT_TRUE(run_second_start(30.0, 100.0));
  EXPECT_FALSE(run_second_start(20.0, 100.0));
  EXPECT_TRUE(run_second_start(-3.0, 0.0));
  EXPECT_TRUE(run_second_start(-3.0, -1.0));
}

}  // namespace
}  // namespace chainsim
