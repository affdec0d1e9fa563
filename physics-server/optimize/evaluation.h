// One individual's evaluation: its scene written to a work directory, a real
// co-simulation in a child process (chainsim-evaluate: the run_scene of
// `chainsim run`), and the score read from the run directory it leaves. Local
// workers and MPI ranks both run evaluations through this.
#pragma once

#include <chrono>
#include <limits>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cosim/child_process.h"
#include "optimize/genome.h"
#include "optimize/objective.h"

namespace chainsim {

struct Problem;

// what to evaluate: an individual of a batch, its key and its run's seed
struct EvalTask {
  size_t index = 0;
  Phenotype phenotype;
  std::string key;
  uint64_t seed = 0;
  int trials = 1;          // runs, one after the other: trials first_trial .. first_trial + trials - 1
  int first_trial = 0;     // the search's trials count from 0, verification's fresh ones from kFreshTrial
  std::string solver;      // "exact": the converged solver (verification); "": the scene's
  std::string target;      // "native" or "pic" for every endpoint (verification); "": the problem's
};

// verification's trials: seeds the search never uses (it runs at most 1000 trials)
constexpr int kFreshTrial = 1000;

// what an evaluation gives; the same for the same task wherever it runs,
// except wall_s
struct EvalResult {
  double fitness = 0;             // in the objective's sense; failed_fitness when failed
  std::vector<double> measures;   // one per measure; NaN when not measured, inf when never reached
  bool failed = false;
  std::string why;                // the fault or the broken constraint
  std::string early_stop;         // a stop_when rule ended a run early: what it saw
  int trials = 1;                 // runs scored (fewer than asked when one failed)
  double fitness_sd = std::numeric_limits<double>::quiet_NaN();   // over the trials; NaN for one
  double fitness_min = std::numeric_limits<double>::quiet_NaN();
  double fitness_max = std::numeric_limits<double>::quiet_NaN();
  double wall_s = 0;              // wall-clock seconds of the simulation
  // the run could not be done for a reason of the machine, not of the
  // design (a full disk, the evaluator killed from outside, an internal
  // error, a module killed by SIGKILL or SIGTERM): `why` says what; no
  // verdict, never journaled, and the search stops (infrastructure_fault)
  bool infra = false;
  bool operator==(const EvalResult& o) const;
};

// whether a run's end was the machine's fault rather than the design's: the
// evaluator's exit status (an exit code other than 0 finished, 2 module
// fault, 4 divergence, 6 silent module; or a signal), or a module ended by a
// signal nobody's firmware sends itself (SIGKILL: the OOM killer or a user;
// SIGTERM, SIGHUP, SIGINT). Returns the reason, or "" for a verdict.
std::string infrastructure_fault(const ExitStatus& evaluator, const std::string& run_fault);

// thrown by the search when an evaluation was an infrastructure fault: the
// search stops after its last complete generation, nothing is recorded for
// that individual, and --resume runs it again
struct InfrastructureError : std::runtime_error {
  InfrastructureError(const std::string& what, bool disk_full)
      : std::runtime_error(what), disk_full(disk_full) {}
  bool disk_full;
};

// the result of a score (combine_trials, failed_score)
EvalResult eval_result_of(const Score& s, double wall_s);

// JSON (non-finite numbers as the strings "inf", "-inf", "nan"); from_json
// throws nlohmann::json::exception on a malformed object
nlohmann::json eval_result_to_json(const EvalResult& r);
EvalResult eval_result_from_json(const nlohmann::json& j);

// the seed of trial r of an individual whose run seed is seed (r = 0: seed itself)
uint64_t trial_seed(uint64_t seed, int trial);

// "module 1 (rotation, pid 4242) closed ..." -> "module 1 (rotation) closed ...":
// a fault's words without what changes from run to run
std::string deterministic_fault_text(const std::string& text);

struct EvalContext {
  const Problem* problem = nullptr;
  std::string evaluator_exe;  // the program that runs a scene: chainsim-evaluate SCENE OUT_DIR TIMEOUT_S
  std::string work_dir;       // where evaluations write their runs
  bool keep_runs = false;     // keep each run directory (else removed once scored)
};

// a running evaluation: construct to start it, poll until done. It runs the
// individual task.trials times, one after the other, each with its own seed
// (trial_seed) and start pose (evaluation.perturb), and scores them with
// combine_trials; a failed trial ends it.
class Evaluation {
 public:
  // dir: where to run (default: a fresh directory under ctx.work_dir)
  Evaluation(const EvalContext& ctx, EvalTask task, const std::string& dir = "");
  Evaluation(const Evaluation&) = delete;
  Evaluation& operator=(const Evaluation&) = delete;

  // non-blocking; true once the result is ready
  bool poll();
  // ends the simulation at once (Ctrl-C); no result
  void terminate();
  const EvalTask& task() const { return task_; }
  const EvalResult& result() const { return result_; }
  pid_t pid() const { return child_.pid(); }
  // the run directory of the task's r-th trial (removed once scored unless kept)
  std::string run_dir(int r = 0) const;

 private:
  std::string scene_path(int r) const;
  void start_trial();
  void finish(const ExitStatus& st);

  const EvalContext& ctx_;
  EvalTask task_;
  std::string dir_;
  ChildProcess child_;
  std::chrono::steady_clock::time_point t0_;
  bool done_ = false;
  std::vector<Score> scores_;   // of the trials run so far
  EvalResult result_;
};

// runs one evaluation to the end, blocking; with dir, in dir and kept there
// (dir/scene.yaml, dir/run/): the best's replay, tests
EvalResult evaluate_now(const EvalContext& ctx, const EvalTask& task, const std::string& dir = "");

}  // namespace chainsim
