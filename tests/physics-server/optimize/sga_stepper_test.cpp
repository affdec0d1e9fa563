// pagmo's sga one generation at a time: deterministic from the seed, its
// population the best of parents and offspring, and a working GA.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "optimize/sga_stepper.h"

using namespace chainsim;

namespace {

GenomeSpec digits(int n) {
  GenomeSpec g;
  for (int i = 0; i < n; ++i) {
    ParamGene p;
    p.target = "central.d" + std::to_string(i);
    p.name = "d" + std::to_string(i);
    p.min = 0;
    p.max = 9;
    g.params.push_back(p);
  }
  return g;
}

// a separable landscape: distance of each digit from 3, 1, 4, 1, 5, 9, 2, 6
double cost(const Genes& g) {
  static const int target[] = {3, 1, 4, 1, 5, 9, 2, 6};
  double c = 0;
  for (size_t i = 0; i < g.size(); ++i) c += std::abs(static_cast<int>(g[i]) - target[i]);
  return c;
}

std::vector<double> costs(const std::vector<Genes>& gs) {
  std::vector<double> f;
  for (const auto& g : gs) f.push_back(cost(g));
  return f;
}

GaSettings settings(uint64_t seed) {
  GaSettings ga;
  ga.population = 20;
  ga.seed = seed;
  return ga;
}

}  // namespace

TEST(SgaStepper, TheSameSeedGivesTheSameSearch) {
  const GenomeSpec g = digits(6);
  SgaStepper a(g, settings(5)), b(g, settings(5)), c(g, settings(6));
  EXPECT_EQ(a.initial(), b.initial());
  EXPECT_NE(a.initial(), c.initial());
  for (SgaStepper* s : {&a, &b}) s->set_population(s->initial(), costs(s->initial()));
  for (int gen = 1; gen <= 5; ++gen) {
    const auto oa = a.offspring(gen), ob = b.offspring(gen);
    EXPECT_EQ(oa, ob);
    EXPECT_EQ(a.offspring(gen), oa);  // asking again changes nothing
    a.advance(gen, costs(oa));
    b.advance(gen, costs(ob));
    EXPECT_EQ(a.population(), b.population());
  }
}

TEST(SgaStepper, ThePopulationIsTheBestOfParentsAndOffspring) {
  const GenomeSpec g = digits(6);
  SgaStepper s(g, settings(3));
  const auto init = s.initial();
  ASSERT_EQ(init.size(), 20u);
  for (const auto& x : init)
    for (int64_t v : x) EXPECT_TRUE(v >= 0 && v <= 9);
  s.set_population(init, costs(init));
  const auto off = s.offspring(1);
  ASSERT_EQ(off.size(), 20u);
  std::vector<double> all = costs(init), of = costs(off);
  all.insert(all.end(), of.begin(), of.end());
  std::sort(all.begin(), all.end());
  s.advance(1, of);
  std::vector<double> kept = s.fitness();
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(kept, std::vector<double>(all.begin(), all.begin() + 20));
  EXPECT_THROW(s.advance(1, of), std::logic_error);  // no offspring() pending
}

TEST(SgaStepper, FindsTheOptimumOfASeparableProblem) {
  // 10^8 individuals; 20 per generation for 60 generations sees at most 1220 of them
  const GenomeSpec g = digits(8);
  SgaStepper s(g, settings(11));
  s.set_population(s.initial(), costs(s.initial()));
  const double start = *std::min_element(s.fitness().begin(), s.fitness().end());
  for (int gen = 1; gen <= 60; ++gen) s.advance(gen, costs(s.offspring(gen)));
  EXPECT_GT(start, 3);
  EXPECT_EQ(*std::min_element(s.fitness().begin(), s.fitness().end()), 0);
}
