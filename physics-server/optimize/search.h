// The design search: generations of individuals evaluated by a pool, the
// cache, the history, a checkpoint after every generation, best.yaml, and
// progress on stderr. The GA is pagmo's sga (sga_stepper.h); an exhaustive
// search evaluates every individual of the genome instead, in gene order, a
// population's worth per "generation" (the paper's 6.1 tried every chain).
#pragma once

#include <cstdint>
#include <string>

#include "optimize/checkpoint.h"
#include "optimize/evaluator_pool.h"
#include "optimize/problem.h"

namespace chainsim {

struct SearchOptions {
  std::string out_dir;
  bool resume = false;
  bool quiet = false;        // no progress lines
};

struct SearchSummary {
  bool interrupted = false;
  int generations_done = -1; // the last generation completed
  BestSoFar best;
  uint64_t evaluations = 0, simulations = 0, cache_hits = 0;
  double wall_s = 0;         // this session's
};

// what a search's directory holds
std::string history_path(const std::string& out_dir);     // history.csv
std::string checkpoint_path(const std::string& out_dir);  // checkpoint.json
std::string journal_path(const std::string& out_dir);     // evaluations.jsonl
std::string best_scene_path(const std::string& out_dir);  // best.yaml

// the last generation the search will run (exhaustive: as many as needed)
int last_generation(const Problem& pr);

// runs (or resumes) the search; throws ProblemError, CheckpointError,
// CacheError or std::runtime_error with a message for the user
SearchSummary run_search(const Problem& pr, const SearchOptions& opt, EvaluatorPool& pool);

// the task of the best (or any) individual: its phenotype, key and seed
EvalTask individual_task(const Problem& pr, const Genes& genes, size_t index);

// the best individual's scene, with a comment header saying what it is
std::string best_scene_text(const Problem& pr, const BestSoFar& best);

}  // namespace chainsim
