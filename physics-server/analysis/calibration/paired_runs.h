// Two fits at once on one core. A model run (the bench's closed form,
// servo_stand.h) is a chain of dependent operations the CPU mostly waits on;
// two independent runs stepped side by side (simulate_benches) overlap and
// take about 0.75-0.95 of the time of the two one after the other. The
// calibration's independent work (its candidates, its starts, a parameter's
// two sides in the intervals) is therefore run as tasks, two at a time:
// whenever both tasks wait for a model run, the two runs are simulated as
// one batch (simulate_batch).
//
// Every piece of work that runs the model is handed the strand it runs on,
// a ModelRuns, and asks it for its runs: the caller's own (a run simulated
// at once), or that of a worker of run_paired. The fit's objective gets it
// through NLopt's data pointer with the rest of the fit. The tasks run on the
// caller's thread, each on a worker of its own (a coroutine with its own
// stack, ucontext): a task's model run gives control back to run_paired,
// which, once every worker has asked for a run or has no task left,
// simulates the runs asked for in one batch and resumes the workers with
// their results. No thread, lock or wait is involved: a task sees exactly
// the results it would see alone, in the same order, and the tasks may share
// the FitProblem. What they write must be their own (a slot of a vector,
// say); messages are kept in order by the caller. A task's strand is named
// `runs` as its caller's is, so that inside the task the caller's strand,
// which must not be asked while its task runs, cannot be named by mistake.
#pragma once

#include <exception>
#include <functional>
#include <vector>

#include "analysis/servo_bench/servo_stand.h"

namespace chainsim {

// one model run: the bench's response (closed form) to the set-points, the
// first `rows` samples
struct RunRequest {
  const BenchConfig* bench = nullptr;
  const std::vector<double>* t_s = nullptr;
  const std::vector<double>* setpoint_deg = nullptr;
  size_t rows = SIZE_MAX;
};
struct BatchResult {
  std::vector<BenchSample> samples;
  std::exception_ptr error;   // simulate_bench's error for this run (then no samples)
};

// the simulations made (a batch's group of runs stepped together counts
// once) and the runs that were stepped together with another
struct PairedRunStats {
  int groups = 0;
  int runs_together = 0;
};

// simulate these runs: those on the same set-points (the same vectors) and
// step stepped side by side (simulate_benches), each giving the bytes
// simulate_bench gives it alone; results in the order of the batch. A
// group's error (its set-points') is every one of its runs'. stats, when
// given, gains the simulations
std::vector<BatchResult> simulate_batch(const std::vector<RunRequest>& batch, PairedRunStats* stats = nullptr);

struct PairedWorker;   // paired_runs.cpp

// the strand a piece of the calibration's work runs on (see above)
class ModelRuns {
 public:
  ModelRuns() = default;
  ModelRuns(const ModelRuns&) = delete;
  ModelRuns& operator=(const ModelRuns&) = delete;

  // the bench's response (simulate_bench, closed form, the first `rows`
  // samples): on a worker, handed to run_paired's batch; on the caller's own
  // strand, simulate_bench itself. Its errors are simulate_bench's (the
  // set-points': a batch's runs on them share them, so all of them throw)
  std::vector<BenchSample> simulate(const BenchConfig& b, const std::vector<double>& t_s,
                                    const std::vector<double>& setpoint_deg, size_t rows);
  // the runs made on this strand: a task's own (its nested tasks' included),
  // or the caller's, which gains its tasks' runs when run_paired returns;
  // the runs of a stretch of work are the difference
  int count() const { return runs_; }
  // the simulations made for this strand and its tasks so far
  PairedRunStats stats() const { return stats_; }

 private:
  friend struct PairedWorker;
  friend void run_paired(ModelRuns& runs, const std::vector<std::function<void(ModelRuns&)>>& tasks);
  int runs_ = 0;
  PairedRunStats stats_;
  PairedWorker* worker_ = nullptr;   // the worker this strand is (none: the caller's own)
};

// runs the tasks, two at a time as above, each given its own strand, and
// returns when all are done; the first exception a task throws is rethrown
// here (the tasks not yet started are not run). With fewer than two tasks
// they run on `runs`. Inside a task (runs: the task's strand) they run one
// after the other on it while the other task still runs, and the rest two at
// a time once it has ended (inside the last task left, a pair of their own).
void run_paired(ModelRuns& runs, const std::vector<std::function<void(ModelRuns&)>>& tasks);

// on (the default) or off: off, run_paired runs the tasks one after the
// other, with the same results (for comparisons)
void set_paired_runs(bool on);

// run_paired over the tasks each(strand, 0), each(strand, 1) ... each(strand, n - 1)
void run_paired_each(ModelRuns& runs, size_t n, const std::function<void(ModelRuns&, size_t)>& each);

}  // namespace chainsim
