// pagmo's simple genetic algorithm (pagmo::sga) driven one generation at a
// time, with the evaluations taken out of it so that they can run in
// parallel. sga makes its offspring (selection, crossover, mutation) before
// it evaluates any of them, so a generation is run twice from the same seed:
// first with a problem that only records which offspring it asks for, then,
// once those are evaluated elsewhere, with a problem that answers from the
// results in the same order. Every operator is pagmo's; the genes are
// integers (pagmo's integer part), so chains and stepped parameters need no
// rounding. Each generation's algorithm is seeded from the search seed and
// the generation number, so the search depends on nothing else.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "optimize/genome.h"
#include "optimize/problem.h"

namespace chainsim {

class SgaStepper {
 public:
  SgaStepper(const GenomeSpec& genome, const GaSettings& ga);
  ~SgaStepper();
  SgaStepper(const SgaStepper&) = delete;
  SgaStepper& operator=(const SgaStepper&) = delete;

  // the initial population: ga.population random individuals (pagmo's
  // random_decision_vector, seeded from the search seed)
  std::vector<Genes> initial() const;
  // sets the population and its fitness (minimised: pagmo's sense)
  void set_population(const std::vector<Genes>& genes, const std::vector<double>& f);
  // the offspring that generation (>= 1) evaluates, in sga's order
  std::vector<Genes> offspring(int generation);
  // sga's next population (parents and offspring, the best ga.population of
  // them) from the offspring's fitness, in the order offspring() gave
  void advance(int generation, const std::vector<double>& offspring_f);
  const std::vector<Genes>& population() const { return genes_; }
  const std::vector<double>& fitness() const { return f_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<Genes> genes_;
  std::vector<double> f_;
  std::vector<Genes> pending_;   // offspring() of the generation not yet advanced
  int pending_generation_ = -1;
};

// the seed of generation g's algorithm (pagmo takes 32 bits)
unsigned sga_generation_seed(uint64_t search_seed, int generation);

}  // namespace chainsim
