// The winners' checks without simulations: which individuals lead, when
// their ranking is within the noise of their trials, which verdicts flip
// under verification, and migration between islands.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "optimize/search.h"
#include "optimize/verify.h"

using namespace chainsim;

namespace {

HistoryRow row(const std::string& key, double f, int trials = 1, double sd = std::nan(""), bool failed = false,
               const std::string& why = "") {
  HistoryRow r;
  r.genome = key;
  r.result.fitness = f;
  r.result.trials = trials;
  r.result.fitness_sd = sd;
  r.result.failed = failed;
  r.result.why = why;
  return r;
}

Problem maximising(int trials = 0) {
  Problem pr;
  pr.objective.maximize = true;
  pr.evaluation.trials = trials;
  return pr;
}

}  // namespace

TEST(Verify, LeadersAreTheBestDistinctPassingOnesFirst) {
  const Problem pr = maximising();
  const auto top = leaders(pr, {row("A", 1), row("B", 5, 1, NAN, true, "constraint"), row("C", 3), row("A", 1),
                                row("D", 2)},
                           3);
  ASSERT_EQ(top.size(), 3u);
  EXPECT_EQ(top[0].genome, "C");
  EXPECT_EQ(top[1].genome, "D");
  EXPECT_EQ(top[2].genome, "A");
  Problem mn = pr;
  mn.objective.maximize = false;
  EXPECT_EQ(leaders(mn, {row("A", 1), row("C", 3)}, 5)[0].genome, "A");
}

TEST(Verify, TheRankingIsWithinTheNoiseWhenTheGapsAreUnderTwoStandardErrors) {
  const Problem pr = maximising();
  // sd 0.3 over 4 trials: se 0.15, the difference's 0.21, twice that 0.42
  const std::string w = noise_warning(pr, {row("A", 1.0, 4, 0.3), row("B", 0.7, 4, 0.3), row("C", 0.1, 4, 0.3)});
  EXPECT_EQ(w.rfind("the ranking of the top 2 is within the noise", 0), 0u) << w;
  EXPECT_EQ(noise_warning(pr, {row("A", 1.0, 4, 0.01), row("B", 0.7, 4, 0.01)}), "");
  // all three close: the top 3
  EXPECT_EQ(noise_warning(pr, {row("A", 1.0, 4, 0.3), row("B", 0.9, 4, 0.3), row("C", 0.8, 4, 0.3)})
                .rfind("the ranking of the top 3", 0),
            0u);
  // one trial: unknown, and said only when the problem fixed it
  EXPECT_EQ(noise_warning(maximising(1), {row("A", 1.0), row("B", 0.9)}).rfind("one trial per individual", 0), 0u);
  EXPECT_EQ(noise_warning(maximising(0), {row("A", 1.0), row("B", 0.9)}), "");
}

TEST(Verify, FlagsSayWhichVerdictFlipsAndWhy) {
  VerifiedLeader v;
  v.search = row("TRRH", 24.9);
  v.fresh.fitness = 25.1;
  v.has_exact = true;
  v.exact.failed = true;
  v.exact.why = "constraint: out_s = inf > 45";
  v.has_pic = true;
  v.pic.fitness = 25.0;
  auto f = verdict_flags(v);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0], "passes with QuickStep, fails with the solver converged (constraint: out_s = inf > 45): the "
                  "verdict rests on the fast solver's give");
  v.fresh.failed = true;
  v.fresh.why = "trial 2 of 3: constraint: out_s = 46 > 45";
  v.exact.failed = false;
  f = verdict_flags(v);
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0], "passed in the search, fails with fresh seeds (trial 2 of 3: constraint: out_s = 46 > 45)");
  EXPECT_EQ(f[1], "fails with QuickStep, passes with the solver converged");
  EXPECT_EQ(f[2], "fails native, passes on the board's binaries");
}

TEST(Islands, MigrantsReplaceTheWorstWhereTheyAreBetterAndNotThere) {
  Checkpoint::Island src{{{1}, {2}, {3}}, {0.5, 0.1, 0.3}};  // pagmo's sense: 0.1 best
  Checkpoint::Island dst{{{7}, {8}, {9}}, {0.2, 0.9, 0.4}};
  migrate_best(src, 2, &dst);
  // {2} (0.1) replaces the worst {8} (0.9); {3} (0.3) replaces {9} (0.4)
  EXPECT_EQ(dst.genes, (std::vector<std::vector<int64_t>>{{7}, {2}, {3}}));
  EXPECT_EQ(dst.f, (std::vector<double>{0.2, 0.1, 0.3}));
  // nothing better, or already there: nothing moves
  Checkpoint::Island same = dst;
  migrate_best(src, 3, &same);
  EXPECT_EQ(same.genes, dst.genes);
}
