#include "optimize/sga_stepper.h"
#include "physics/splitmix64.h"

#include <pagmo/algorithms/sga.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <pagmo/types.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace chainsim {

namespace {

// what the problem answers sga: record the offspring asked for, or replay
// their fitness in the order they were recorded
struct Oracle {
  bool replay = false;
  std::vector<pagmo::vector_double> asked;
  std::vector<double> answers;
  size_t next = 0;
};

// the pagmo problem (UDP): integer genes 0..upper, one minimised objective
struct GenomeUdp {
  std::shared_ptr<Oracle> oracle;
  pagmo::vector_double lb, ub;

  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    Oracle& o = *oracle;
    if (!o.replay) {
      o.asked.push_back(x);
      return {0.0};
    }
    if (o.next >= o.answers.size() || o.asked[o.next] != x)
      throw std::logic_error("sga asked for a different offspring on its second pass (internal error)");
    return {o.answers[o.next++]};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const { return {lb, ub}; }
  pagmo::vector_double::size_type get_nix() const { return lb.size(); }
  std::string get_name() const { return "chainsim design search"; }
};

pagmo::vector_double to_pagmo(const Genes& g) { return pagmo::vector_double(g.begin(), g.end()); }

Genes from_pagmo(const pagmo::vector_double& x) {
  Genes g;
  for (double v : x) g.push_back(static_cast<int64_t>(std::llround(v)));
  return g;
}

}  // namespace

unsigned sga_generation_seed(uint64_t search_seed, int generation) {
  return static_cast<unsigned>(splitmix64(splitmix64(search_seed) + static_cast<uint64_t>(generation)) >> 32);
}

struct SgaStepper::Impl {
  GaSettings ga;
  size_t n_genes = 0;
  std::shared_ptr<Oracle> oracle = std::make_shared<Oracle>();
  pagmo::problem problem;

  pagmo::sga algorithm(int generation) const {
    const double m = ga.mutation_probability >= 0 ? ga.mutation_probability : 1.0 / static_cast<double>(n_genes);
    // param_m: the width of gaussian mutation; uniform ignores it but pagmo checks it is in [0, 1]
    return pagmo::sga(1u, ga.crossover_probability, 1.0, m, ga.mutation_width,
                      static_cast<unsigned>(ga.selection_size), ga.crossover, ga.mutation, ga.selection,
                      sga_generation_seed(ga.seed, generation));
  }
  pagmo::population population(const std::vector<Genes>& genes, const std::vector<double>& f) const {
    pagmo::population pop(problem, 0u, sga_generation_seed(ga.seed, 0));
    for (size_t i = 0; i < genes.size(); ++i) pop.push_back(to_pagmo(genes[i]), {f[i]});
    return pop;
  }
};

SgaStepper::SgaStepper(const GenomeSpec& genome, const GaSettings& ga) : impl_(std::make_unique<Impl>()) {
  impl_->ga = ga;
  GenomeUdp udp;
  udp.oracle = impl_->oracle;
  for (int64_t u : genome.gene_upper()) {
    udp.lb.push_back(0.0);
    udp.ub.push_back(static_cast<double>(u));
  }
  impl_->n_genes = udp.lb.size();
  impl_->problem = pagmo::problem(udp);
}

SgaStepper::~SgaStepper() = default;

std::vector<Genes> SgaStepper::initial() const {
  pagmo::population pop(impl_->problem, 0u, sga_generation_seed(impl_->ga.seed, 0));
  std::vector<Genes> out;
  for (int i = 0; i < impl_->ga.population; ++i) out.push_back(from_pagmo(pop.random_decision_vector()));
  return out;
}

void SgaStepper::set_population(const std::vector<Genes>& genes, const std::vector<double>& f) {
  genes_ = genes;
  f_ = f;
  pending_.clear();
  pending_generation_ = -1;
}

std::vector<Genes> SgaStepper::offspring(int generation) {
  Oracle& o = *impl_->oracle;
  o.replay = false;
  o.asked.clear();
  impl_->algorithm(generation).evolve(impl_->population(genes_, f_));
  pending_.clear();
  for (const auto& x : o.asked) pending_.push_back(from_pagmo(x));
  pending_generation_ = generation;
  return pending_;
}

void SgaStepper::advance(int generation, const std::vector<double>& offspring_f) {
  if (generation != pending_generation_ || offspring_f.size() != pending_.size())
    throw std::logic_error("SgaStepper::advance without the matching offspring()");
  Oracle& o = *impl_->oracle;
  o.replay = true;
  o.answers = offspring_f;
  o.next = 0;
  const pagmo::population next = impl_->algorithm(generation).evolve(impl_->population(genes_, f_));
  if (o.next != o.answers.size()) throw std::logic_error("sga evaluated fewer offspring on its second pass");
  genes_.clear();
  f_.clear();
  for (size_t i = 0; i < next.size(); ++i) {
    genes_.push_back(from_pagmo(next.get_x()[i]));
    f_.push_back(next.get_f()[i][0]);
  }
  o.replay = false;
  pending_.clear();
  pending_generation_ = -1;
}

}  // namespace chainsim
