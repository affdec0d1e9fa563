// Two fits at once on one core. A model run (the bench's closed form,
// servo_stand.h) is a chain of dependent divisions the CPU mostly waits on;
// two independent runs stepped side by side (simulate_benches) overlap and
// take about 0.6-0.7 of the time of the two one after the other. The
// calibration's independent work (its candidates, its starts, a parameter's
// two sides in the intervals) is therefore run as tasks, two at a time:
// whenever both tasks wait for a model run, the two runs are stepped
// together.
//
// The tasks run on two threads, but only one of them runs at any moment (the
// other waits for its model run or for its turn; pinned to one core with
// taskset a calibration takes the same time): a task sees exactly the
// results it would see alone, in the same order, and the tasks may share the
// FitProblem. What they write must be their own (a slot of a vector, say);
// messages are kept in order by the caller.
#pragma once

#include <functional>
#include <vector>

#include "analysis/servo_bench/servo_stand.h"

namespace chainsim {

// runs the tasks, two at a time as above, and returns when all are done; the
// first exception a task throws is rethrown here (the tasks not yet started
// are not run). With fewer than two tasks they run on the calling thread.
// Inside a task they run one after the other while the other task still
// runs, and the rest two at a time once it has ended (inside the last task
// left, a pair of their own).
void run_paired(const std::vector<std::function<void()>>& tasks);

// on (the default) or off: off, run_paired runs the tasks one after the
// other on the calling thread, with the same results (for comparisons)
void set_paired_runs(bool on);

// run_paired over the tasks each(0), each(1) ... each(n - 1)
void run_paired_each(size_t n, const std::function<void(size_t)>& each);

// the bench's response (simulate_bench, closed form, the first `rows`
// samples): inside run_paired's tasks, stepped together with the other
// task's run when both wait for one on the same set-points; elsewhere
// simulate_bench itself. Its errors are simulate_bench's (the set-points':
// a pair shares them, so both of its runs throw)
std::vector<BenchSample> paired_simulate(const BenchConfig& b, const std::vector<double>& t_s,
                                         const std::vector<double>& setpoint_deg, size_t rows);

// the runs paired_simulate made on the calling thread, and in the tasks it
// ran through run_paired: the runs of a stretch of work are the difference
// (p.model_runs, shared, counts the other task's runs meanwhile too)
int thread_model_runs();

}  // namespace chainsim
