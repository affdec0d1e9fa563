// The greedy search's stages (effect_search.h), each on its own, on a record
// of the bench model with a 3 degree deadband (bench_record.h); the effects
// other than the one a test is about are marked used, so that each stage
// fits a few candidates only. Each stage takes the problem as it is and
// gives what it found; the loss's unit and the model runs are the caller's.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "analysis/calibration/effect_catalogue.h"
#include "analysis/calibration/effect_search.h"
#include "analysis/calibration/paired_runs.h"
#include "analysis/calibration/regimes.h"
#include "bench_record.h"

namespace chainsim {
namespace {

const CalibrationProgress kQuiet = [](const std::string&) {};

// every effect name but `keep`
std::set<std::string> all_but(const std::vector<std::string>& keep) {
  std::set<std::string> used;
  for (const Effect& ef : effect_catalogue())
    if (std::find(keep.begin(), keep.end(), ef.name) == keep.end()) used.insert(ef.name);
  return used;
}

struct Record {
  FitProblem p;             // with the loss's unit of the base's first fit
  std::vector<int> regime;
  Fit base;                 // the base fitted without effects
};

// the base a little off the datasheet, `deadband` degrees of deadband (0: none)
Record record(double deadband) {
  ModelRuns runs;
  BenchConfig truth = test_datasheet();
  truth.servo.kp *= 1.05;
  truth.servo.r *= 0.96;
  truth.servo.deadband_deg = deadband;
  Record r;
  r.p = make_fit_problem(test_datasheet(), bench_record(truth, 7));
  r.regime = classify_regimes(r.p.m, r.p.datasheet.servo.supply_v / r.p.datasheet.servo.r);
  r.p.noise = white_noise_scale(run_model(runs, r.p, r.p.datasheet).residual, r.p.split);
  r.base = fit_model(runs, r.p, {}, std::vector<double>(kNumBase, 1.0), Samples::training, kMaxEvalBase);
  return r;
}

// the round's unit is the white noise the current model leaves, in a copy of
// the problem; the problem given is not changed
TEST(SearchStages, TheRoundsNoiseGoesIntoACopyOfTheProblem) {
  ModelRuns runs;
  const Record r = record(3.0);
  const NoiseScale n = round_noise(runs, r.p, r.base);
  const FitProblem q = with_noise(r.p, n);
  EXPECT_EQ(q.noise.angle, n.angle);
  EXPECT_EQ(q.noise.current, n.current);
  EXPECT_NE(r.p.noise.angle, n.angle);
  EXPECT_EQ(q.m.angle, r.p.m.angle);
  // the differences of the residual see the measurement's white noise (0.2
  // deg, 2 mA) within 15 %, not the deadband the base misses
  EXPECT_NEAR(n.angle * r.p.sa, 0.2, 0.03);
  EXPECT_NEAR(n.current * r.p.si, 0.002, 0.0003);
}

// 1: the reference is never worse than the current model, and its residual
// covers every sample
TEST(SearchStages, TheReferenceIsRefittedFromTwoStarts) {
  ModelRuns runs;
  const Record r = record(3.0);
  const FitProblem p = with_noise(r.p, round_noise(runs, r.p, r.base));
  const Fit cur = evaluate_fit(runs, p, r.base.effects, r.base.x);
  const int before = runs.count();
  const Reference ref = fit_reference(runs, p, r.base, kQuiet);
  EXPECT_LE(ref.fit.train, cur.train);
  EXPECT_EQ(ref.residual.size(), p.m.size());
  EXPECT_TRUE(ref.fit.effects.empty());
  // two starts of at most kMaxEvalBase runs each, their final evaluations,
  // the current model's evaluation and the residual
  EXPECT_GT(runs.count() - before, 2);
  EXPECT_LE(runs.count() - before, 2 * (kMaxEvalBase + 1) + 2);
}

// 2-5 on the deadband record, with only the deadband and the supply sag
// left to find: the deadband passes the screen and is fitted in full, the
// supply sag's forms show no effect, so their refining forms are not
// fitted, and the deadband is chosen
TEST(SearchStages, ADeadbandIsFittedAndChosen) {
  ModelRuns runs;
  const Record r = record(3.0);
  const FitProblem p = with_noise(r.p, round_noise(runs, r.p, r.base));
  const Reference ref = fit_reference(runs, p, r.base, kQuiet);
  const std::set<std::string> used = all_but({"deadband", "supply_sag"});
  std::vector<std::string> lines;
  const CalibrationProgress say = [&](const std::string& l) { lines.push_back(l); };

  std::vector<Candidate> cands = fit_candidates(runs, p, ref, r.regime, used, say);
  // every form that refines no other, in the catalogue's order
  std::vector<int> forms;
  for (int e = 0; e < static_cast<int>(effect_catalogue().size()); ++e)
    if (!used.count(effect_catalogue()[e].name) && !*effect_catalogue()[e].refines) forms.push_back(e);
  ASSERT_EQ(cands.size(), forms.size());
  const Candidate* db = nullptr;
  for (size_t i = 0; i < cands.size(); ++i) {
    EXPECT_EQ(cands[i].effect, forms[i]);
    EXPECT_GT(cands[i].runs, 0);
    // the record's deadband is the model's dead zone (of the two forms)
    if (std::string(effect_catalogue()[cands[i].effect].name) == "deadband" &&
        std::string(effect_catalogue()[cands[i].effect].variant) == "dead_zone")
      db = &cands[i];
  }
  ASSERT_NE(db, nullptr);
  EXPECT_FALSE(db->screen.stopped);
  EXPECT_LT(db->fit.train, ref.fit.train);
  EXPECT_EQ(db->resolution, 0.0);   // finished in stage 3 (a smooth form)

  const std::vector<Candidate> first = cands;
  fit_second_starts(runs, p, ref.fit, r.regime, &cands, say);
  for (size_t i = 0; i < cands.size(); ++i) {
    if (cands[i].screen.stopped) {
      EXPECT_EQ(cands[i].runs, first[i].runs);   // not fitted further
      continue;
    }
    EXPECT_LE(cands[i].fit.train, first[i].fit.train);
    EXPECT_EQ(cands[i].second_start_skipped, !run_second_start(cands[i].first_gain, cands[i].round_first_gain));
    EXPECT_GT(cands[i].resolution, 0.0);
  }
  EXPECT_NEAR(db->fit.x[kNumBase], 3.0, 0.3);

  const size_t n = cands.size();
  lines.clear();
  fit_refining_forms(runs, p, ref, r.regime, used, &cands, say);
  int refining = 0;
  for (const Effect& ef : effect_catalogue()) refining += std::string(ef.name) == "supply_sag" && *ef.refines;
  // no supply sag in the record: its simpler forms show none, the refining ones are passed over, each with its line
  EXPECT_EQ(cands.size(), n);
  EXPECT_EQ(static_cast<int>(lines.size()), refining);
  for (const std::string& l : lines) EXPECT_NE(l.find("shows no effect this round"), std::string::npos) << l;

  const Selection sel = select_candidate(runs, p, ref.fit, &cands, say);
  ASSERT_GE(sel.chosen, 0);
  EXPECT_STREQ(effect_catalogue()[cands[sel.chosen].effect].name, "deadband");
  EXPECT_TRUE(cands[sel.chosen].accepted);
  for (size_t i = 1; i < cands.size(); ++i) {
    EXPECT_FALSE(cands[i].accepted && static_cast<long>(i) != sel.chosen);
    if (cands[i].fit.valid && cands[i - 1].fit.valid) {
      EXPECT_GE(cands[i - 1].held_out.gain, cands[i].held_out.gain);
    }
  }
  EXPECT_LE(sel.reference.train, ref.fit.train);
}

// 2-5 on a record without a deadband: the deadband's candidate does not pass,
// nothing is chosen, every candidate is rejected
TEST(SearchStages, NothingIsChosenWhereNothingIsMissing) {
  ModelRuns runs;
  const Record r = record(0.0);
  const FitProblem p = with_noise(r.p, round_noise(runs, r.p, r.base));
  const Reference ref = fit_reference(runs, p, r.base, kQuiet);
  const std::set<std::string> used = all_but({"deadband"});
  std::vector<Candidate> cands = fit_candidates(runs, p, ref, r.regime, used, kQuiet);
  fit_second_starts(runs, p, ref.fit, r.regime, &cands, kQuiet);
  fit_refining_forms(runs, p, ref, r.regime, used, &cands, kQuiet);
  // one candidate per form of the deadband
  ASSERT_EQ(cands.size(), effect_variants("deadband").size());
  const Selection sel = select_candidate(runs, p, ref.fit, &cands, kQuiet);
  EXPECT_EQ(sel.chosen, -1);
  for (const Candidate& c : cands) {
    EXPECT_FALSE(c.accepted);
    EXPECT_NE(c.why.find(": rejected"), std::string::npos) << c.why;
  }
}

// the whole search: its model runs go to the caller's state (added to what
// it held), and the state's noise is the last round's loss unit
TEST(SearchStages, TheSearchKeepsItsStateInTheCallers) {
  ModelRuns runs;
  const Record r = record(3.0);
  SearchState st;
  st.model_runs = 5;
  const int before = runs.count();
  const FitProblem p = r.p;
  const EffectSearch s = search_effects(runs, p, r.base, r.regime, st, kQuiet);
  EXPECT_EQ(st.model_runs, 5 + runs.count() - before);
  ASSERT_FALSE(s.rounds.empty());
  EXPECT_EQ(st.noise.angle, s.rounds.back().noise.angle);
  EXPECT_EQ(st.noise.current, s.rounds.back().noise.current);
  EXPECT_EQ(p.noise.angle, r.p.noise.angle);   // the problem as it was given
  ASSERT_EQ(s.model.effects.size(), 1u);
  EXPECT_STREQ(effect_catalogue()[s.model.effects[0]].name, "deadband");
}

}  // namespace
}  // namespace chainsim
