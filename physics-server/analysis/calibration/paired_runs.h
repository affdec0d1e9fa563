// Two fits at once on one core. A model run (the bench's closed form,
// servo_stand.h) is a chain of dependent divisions the CPU mostly waits on;
// two independent runs stepped side by side (simulate_benches) overlap and
// take about 0.6-0.7 of the time of the two one after the other. The
// calibration's independent work (its candidates, its starts, a parameter's
// two sides in the intervals) is therefore run as tasks, two at a time:
// whenever both tasks wait for a model run, the two runs are simulated as
// one batch (simulate_batch).
//
// The tasks run on the caller's thread, each on a worker of its own (a
// coroutine with its own stack, ucontext): a task's model run gives control
// back to run_paired, which, once every worker has asked for a run or has
// no task left, simulates the runs asked for in one batch and resumes the
// workers with their results. No thread, lock or wait is involved: a task
// sees exactly the results it would see alone, in the same order, and the
// tasks may share the FitProblem. What they write must be their own (a slot
// of a vector, say); messages are kept in order by the caller.
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

// simulate these runs: those on the same set-points (the same vectors) and
// step stepped side by side (simulate_benches), each giving the bytes
// simulate_bench gives it alone; results in the order of the batch. A
// group's error (its set-points') is every one of its runs'
std::vector<BatchResult> simulate_batch(const std::vector<RunRequest>& batch);

// runs the tasks, two at a time as above, and returns when all are done; the
// first exception a task throws is rethrown here (the tasks not yet started
// are not run). With fewer than two tasks they run on the caller's strand.
// Inside a task they run one after the other while the other task still
// runs, and the rest two at a time once it has ended (inside the last task
// left, a pair of their own).
void run_paired(const std::vector<std::function<void()>>& tasks);

// on (the default) or off: off, run_paired runs the tasks one after the
// other, with the same results (for comparisons)
void set_paired_runs(bool on);

// run_paired over the tasks each(0), each(1) ... each(n - 1)
void run_paired_each(size_t n, const std::function<void(size_t)>& each);

// the bench's response (simulate_bench, closed form, the first `rows`
// samples): inside run_paired's tasks, handed to run_paired's batch;
// elsewhere simulate_bench itself. Its errors are simulate_bench's (the
// set-points': a batch's runs on them share them, so all of them throw)
std::vector<BenchSample> paired_simulate(const BenchConfig& b, const std::vector<double>& t_s,
                                         const std::vector<double>& setpoint_deg, size_t rows);

// the runs paired_simulate made in the code running now: a task's own (its
// nested tasks' included), or the caller's outside run_paired, which gains
// its tasks' runs when run_paired returns; the runs of a stretch of work are
// the difference
int task_model_runs();

// on this thread so far: the simulations made (a batch's group of runs
// stepped together counts once) and the runs that were stepped together with
// another
struct PairedRunStats {
  int groups = 0;
  int runs_together = 0;
};
PairedRunStats paired_run_stats();

}  // namespace chainsim
