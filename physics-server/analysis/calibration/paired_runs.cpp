// Two fits at once on one core (paired_runs.h).
#include "analysis/calibration/paired_runs.h"

#include <sys/mman.h>
#include <ucontext.h>

#include <cstdint>
#include <exception>
#include <new>

namespace chainsim {

struct PairedScheduler;

// A worker: a coroutine on the caller's thread, with a stack of its own,
// that takes the next task until none is left, handing each task its strand.
// It gives control back to the scheduler only when it asks for a model run
// (or has no task left); the scheduler resumes it with the run's result.
struct PairedWorker {
  ModelRuns runs;           // its strand: runs_ counts its tasks' runs
  PairedScheduler* s = nullptr;
  ucontext_t ctx{};
  void* stack = nullptr;
  bool started = false, finished = false;
  bool waiting = false;     // it has asked for a run (request) and waits for it
  RunRequest request;
  std::vector<BenchSample> out;
  std::exception_ptr run_error;

  // a run asked for by one of its tasks: the scheduler resumes it with the result
  std::vector<BenchSample> ask(const RunRequest& r);
  // the tasks from `first` on, on two workers; caller gains their runs
  static void run_on_workers(ModelRuns& caller, const std::vector<std::function<void(ModelRuns&)>>& tasks,
                             size_t first);
  // inside a task whose partner still runs (the nested tasks go one after the other)
  bool partner_runs() const;
};

struct PairedScheduler {
  const std::vector<std::function<void(ModelRuns&)>>* tasks = nullptr;
  size_t next = 0;          // the next task to start
  std::exception_ptr error; // the first a task threw
  ucontext_t home{};        // the scheduler's own context (on the caller's stack)
  PairedWorker w[2];
  int live = 0;             // workers with tasks still to do
};

namespace {

// a worker's stack: reserved, not committed (the pages a fit touches are a
// few tens of kB), with a guard page below it
constexpr size_t kStackBytes = size_t{8} << 20;
constexpr size_t kGuardBytes = 4096;

bool g_paired = true;

void worker_main(unsigned hi, unsigned lo) {
  PairedWorker& w = *reinterpret_cast<PairedWorker*>((static_cast<uintptr_t>(hi) << 32) | lo);
  PairedScheduler& S = *w.s;
  while (S.next < S.tasks->size() && !S.error) {
    const size_t i = S.next++;
    try {
      (*S.tasks)[i](w.runs);
    } catch (...) {
      if (!S.error) S.error = std::current_exception();
    }
  }
  w.finished = true;
  --S.live;
  // returning resumes S.home (uc_link)
}

// the runs the waiting workers asked for: those on the same set-points and
// step stepped together (simulate_batch), then the workers given their results
void run_requests(PairedScheduler& S, PairedRunStats* stats) {
  std::vector<PairedWorker*> waiting;
  std::vector<RunRequest> batch;
  for (PairedWorker& w : S.w)
    if (w.waiting) waiting.push_back(&w), batch.push_back(w.request);
  std::vector<BatchResult> results = simulate_batch(batch, stats);
  for (size_t i = 0; i < waiting.size(); ++i) {
    waiting[i]->out = std::move(results[i].samples);
    waiting[i]->run_error = results[i].error;
    waiting[i]->waiting = false;
  }
}

}  // namespace

std::vector<BenchSample> PairedWorker::ask(const RunRequest& r) {
  request = r;
  waiting = true;
  swapcontext(&ctx, &s->home);
  if (run_error) std::rethrow_exception(run_error);
  return std::move(out);
}

bool PairedWorker::partner_runs() const { return s->live > 1; }

void PairedWorker::run_on_workers(ModelRuns& caller, const std::vector<std::function<void(ModelRuns&)>>& tasks,
                                  size_t first) {
  PairedScheduler S;
  S.tasks = &tasks;
  S.next = first;
  for (PairedWorker& w : S.w) {
    void* m = mmap(nullptr, kStackBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (m == MAP_FAILED) break;   // no stack to be had: the worker(s) made so far run them all
    mprotect(m, kGuardBytes, PROT_NONE);
    w.s = &S;
    w.runs.worker_ = &w;
    w.stack = m;
    getcontext(&w.ctx);
    w.ctx.uc_stack.ss_sp = m;
    w.ctx.uc_stack.ss_size = kStackBytes;
    w.ctx.uc_link = &S.home;
    const auto a = reinterpret_cast<uintptr_t>(&w);
    makecontext(&w.ctx, reinterpret_cast<void (*)()>(worker_main), 2, static_cast<unsigned>(a >> 32),
                static_cast<unsigned>(a & 0xffffffffu));
    w.started = true;
    ++S.live;
  }
  if (S.live == 0) {   // no worker at all: here, one after the other
    for (size_t i = first; i < tasks.size(); ++i) tasks[i](caller);
    return;
  }
  // every worker with work runs until it asks for a run or has none left;
  // then the runs asked for, together, and again
  for (;;) {
    for (PairedWorker& w : S.w)
      if (w.started && !w.finished && !w.waiting) swapcontext(&S.home, &w.ctx);
    bool any = false;
    for (const PairedWorker& w : S.w) any = any || w.waiting;
    if (!any) break;
    run_requests(S, &caller.stats_);
  }
  for (PairedWorker& w : S.w) {
    caller.runs_ += w.runs.runs_;
    caller.stats_.groups += w.runs.stats_.groups;
    caller.stats_.runs_together += w.runs.stats_.runs_together;
    if (w.stack) munmap(w.stack, kStackBytes);
  }
  if (S.error) std::rethrow_exception(S.error);
}

std::vector<BatchResult> simulate_batch(const std::vector<RunRequest>& batch, PairedRunStats* stats) {
  std::vector<BatchResult> out(batch.size());
  std::vector<bool> done(batch.size(), false);
  for (size_t i = 0; i < batch.size(); ++i) {
    if (done[i]) continue;
    // the runs on the same set-points and step as run i
    std::vector<size_t> group;
    std::vector<const BenchConfig*> benches;
    std::vector<size_t> counts;
    for (size_t j = i; j < batch.size(); ++j) {
      const RunRequest& a = batch[i];
      const RunRequest& b = batch[j];
      if (done[j] || a.t_s != b.t_s || a.setpoint_deg != b.setpoint_deg || a.bench->dt_us != b.bench->dt_us) continue;
      group.push_back(j);
      benches.push_back(b.bench);
      counts.push_back(b.rows);
      done[j] = true;
    }
    try {
      std::vector<std::vector<BenchSample>> sims =
          simulate_benches(benches, *batch[i].t_s, *batch[i].setpoint_deg, BenchSolver::closed_form, counts);
      for (size_t g = 0; g < group.size(); ++g) out[group[g]].samples = std::move(sims[g]);
    } catch (...) {
      for (size_t j : group) out[j].error = std::current_exception();
    }
    if (stats) {
      ++stats->groups;
      if (group.size() > 1) stats->runs_together += static_cast<int>(group.size());
    }
  }
  return out;
}

void set_paired_runs(bool on) { g_paired = on; }

void run_paired(ModelRuns& runs, const std::vector<std::function<void(ModelRuns&)>>& tasks) {
  size_t first = 0;   // the tasks before it have run
  if (g_paired) {
    // inside a task whose partner still runs: one after the other (the task
    // is already paired), until the partner has ended
    while (first < tasks.size() && runs.worker_ && runs.worker_->partner_runs()) tasks[first++](runs);
    if (tasks.size() - first >= 2) return PairedWorker::run_on_workers(runs, tasks, first);
  }
  for (; first < tasks.size(); ++first) tasks[first](runs);
}

void run_paired_each(ModelRuns& runs, size_t n, const std::function<void(ModelRuns&, size_t)>& each) {
  std::vector<std::function<void(ModelRuns&)>> tasks;
  for (size_t i = 0; i < n; ++i) tasks.push_back([&each, i](ModelRuns& strand) { each(strand, i); });
  run_paired(runs, tasks);
}

std::vector<BenchSample> ModelRuns::simulate(const BenchConfig& b, const std::vector<double>& t_s,
                                             const std::vector<double>& setpoint_deg, size_t rows) {
  ++runs_;
  if (worker_) return worker_->ask(RunRequest{&b, &t_s, &setpoint_deg, rows});
  ++stats_.groups;
  return simulate_bench(b, t_s, setpoint_deg, BenchSolver::closed_form, rows);
}

}  // namespace chainsim
