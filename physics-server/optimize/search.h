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
#include "optimize/history.h"
#include "optimize/problem.h"

namespace chainsim {

struct SearchOptions {
  std::string out_dir;
  bool resume = false;
  bool quiet = false;        // no progress lines
};

struct SearchSummary {
  bool interrupted = false;
  int generations_done = -1; // the last generation every island completed
  BestSoFar best;
  uint64_t evaluations = 0, simulations = 0, cache_hits = 0;
  int trials = 0;            // runs per individual after generation 0 (0: not decided)
  std::string trials_note;   // with trials: auto, what generation 0 showed
  double wall_s = 0;         // this session's
  double busy_s = 0;         // summed wall time of the simulations this session ran
};

// what a checkpoint says of the search up to it: its best, counts and
// trials (a resume goes on from it; --verify verifies it)
SearchSummary summary_of(const Checkpoint& cp);

// what a search's directory holds
std::string history_path(const std::string& out_dir);     // history.csv
std::string checkpoint_path(const std::string& out_dir);  // checkpoint.json
std::string journal_path(const std::string& out_dir);     // evaluations.jsonl
std::string best_scene_path(const std::string& out_dir);  // best.yaml

// what a search's checkpoint and journal are tied to: the problem file, the
// base scene, the seed and the GA's settings
std::string search_fingerprint(const Problem& pr);

// the last generation the search will run (exhaustive: as many as needed)
int last_generation(const Problem& pr);

// runs (or resumes) the search; throws ProblemError, CheckpointError,
// CacheError or std::runtime_error with a message for the user
SearchSummary run_search(const Problem& pr, const SearchOptions& opt, EvaluatorPool& pool);

// the task of the best (or any) individual: its phenotype, key and seed
// (one trial; the search sets the trials)
EvalTask individual_task(const Problem& pr, const Genes& genes, size_t index);

// island i's GA settings: the search's, seeded from the search seed and i
// (island 0 keeps the search seed: one island is the plain sga)
GaSettings island_ga(const GaSettings& ga, int island);

// migration between islands: dst's population with the best `m` of src's
// (pagmo's fitness: lower is better) put in place of its worst, each only
// when better and not already there (as pagmo's fair_replace)
void migrate_best(const Checkpoint::Island& src, int m, Checkpoint::Island* dst);

// the trials of generation g's individuals: the problem's, or with trials:
// auto kAutoProbeTrials in generation 0 and `decided` after it
int trials_for_generation(const Problem& pr, int generation, int decided);

// trials: auto's decision after generation 0: kAutoProbeTrials if any
// individual's fitness differed between its trials, else 1; *note says why
int decide_trials(const std::vector<HistoryRow>& generation0, std::string* note);

// the best individual's scene, with a comment header saying what it is (and
// `more`: further comment lines, each starting "# ")
std::string best_scene_text(const Problem& pr, const BestSoFar& best, const std::string& more = "");

}  // namespace chainsim
