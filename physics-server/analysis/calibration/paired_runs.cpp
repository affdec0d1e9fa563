// Two fits at once on one core (paired_runs.h).
#include "analysis/calibration/paired_runs.h"

#include <sys/mman.h>
#include <ucontext.h>

#include <cstdint>
#include <exception>
#include <new>

namespace chainsim {
namespace {

// a strand of work: the caller's own, or a worker of run_paired running its
// tasks one after the other
struct Strand {
  int runs = 0;   // the model runs its tasks made
};

struct Scheduler;

// A worker: a coroutine on the caller's thread, with a stack of its own,
// that takes the next task until none is left. It gives control back to the
// scheduler only when it asks for a model run (or has no task left); the
// scheduler resumes it with the run's result.
struct Worker : Strand {
  Scheduler* s = nullptr;
  ucontext_t ctx{};
  void* stack = nullptr;
  bool started = false, finished = false;
  bool waiting = false;     // it has asked for a run (request) and waits for it
  RunRequest request;
  std::vector<BenchSample> out;
  std::exception_ptr run_error;
};

struct Scheduler {
  const std::vector<std::function<void()>>* tasks = nullptr;
  size_t next = 0;          // the next task to start
  std::exception_ptr error; // the first a task threw
  ucontext_t home{};        // the scheduler's own context (on the caller's stack)
  Worker w[2];
  int live = 0;             // workers with tasks still to do
};

// a worker's stack: reserved, not committed (the pages a fit touches are a
// few tens of kB), with a guard page below it
constexpr size_t kStackBytes = size_t{8} << 20;
constexpr size_t kGuardBytes = 4096;

bool g_paired = true;
thread_local Strand t_base;                 // the thread's own strand
thread_local Strand* t_strand = &t_base;    // the strand whose code runs now
thread_local Worker* t_worker = nullptr;    // the same when it is a worker
thread_local PairedRunStats t_stats;

void worker_main(unsigned hi, unsigned lo) {
  Worker& w = *reinterpret_cast<Worker*>((static_cast<uintptr_t>(hi) << 32) | lo);
  Scheduler& S = *w.s;
  while (S.next < S.tasks->size() && !S.error) {
    const size_t i = S.next++;
    try {
      (*S.tasks)[i]();
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
void run_requests(Scheduler& S) {
  std::vector<Worker*> waiting;
  std::vector<RunRequest> batch;
  for (Worker& w : S.w)
    if (w.waiting) waiting.push_back(&w), batch.push_back(w.request);
  std::vector<BatchResult> results = simulate_batch(batch);
  for (size_t i = 0; i < waiting.size(); ++i) {
    waiting[i]->out = std::move(results[i].samples);
    waiting[i]->run_error = results[i].error;
    waiting[i]->waiting = false;
  }
}

// the tasks from `first` on, on two workers; the caller's strand gains their runs
void run_on_workers(const std::vector<std::function<void()>>& tasks, size_t first) {
  Scheduler S;
  S.tasks = &tasks;
  S.next = first;
  Strand* const caller = t_strand;
  Worker* const caller_worker = t_worker;
  for (Worker& w : S.w) {
    void* m = mmap(nullptr, kStackBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (m == MAP_FAILED) break;   // no stack to be had: the worker(s) made so far run them all
    mprotect(m, kGuardBytes, PROT_NONE);
    w.s = &S;
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
    for (size_t i = first; i < tasks.size(); ++i) tasks[i]();
    return;
  }
  // every worker with work runs until it asks for a run or has none left;
  // then the runs asked for, together, and again
  for (;;) {
    for (Worker& w : S.w) {
      if (!w.started || w.finished || w.waiting) continue;
      t_strand = &w;
      t_worker = &w;
      swapcontext(&S.home, &w.ctx);
      t_strand = caller;
      t_worker = caller_worker;
    }
    bool any = false;
    for (const Worker& w : S.w) any = any || w.waiting;
    if (!any) break;
    run_requests(S);
  }
  for (Worker& w : S.w) {
    caller->runs += w.runs;
    if (w.stack) munmap(w.stack, kStackBytes);
  }
  if (S.error) std::rethrow_exception(S.error);
}

}  // namespace

std::vector<BatchResult> simulate_batch(const std::vector<RunRequest>& batch) {
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
    ++t_stats.groups;
    if (group.size() > 1) t_stats.runs_together += static_cast<int>(group.size());
  }
  return out;
}

void set_paired_runs(bool on) { g_paired = on; }

void run_paired(const std::vector<std::function<void()>>& tasks) {
  size_t first = 0;   // the tasks before it have run
  if (g_paired) {
    // inside a task whose partner still runs: one after the other (the task
    // is already paired), until the partner has ended
    while (first < tasks.size() && t_worker && t_worker->s->live > 1) tasks[first++]();
    if (tasks.size() - first >= 2) return run_on_workers(tasks, first);
  }
  for (; first < tasks.size(); ++first) tasks[first]();
}

void run_paired_each(size_t n, const std::function<void(size_t)>& each) {
  std::vector<std::function<void()>> tasks;
  for (size_t i = 0; i < n; ++i) tasks.push_back([&each, i] { each(i); });
  run_paired(tasks);
}

int task_model_runs() { return t_strand->runs; }

PairedRunStats paired_run_stats() { return t_stats; }

std::vector<BenchSample> paired_simulate(const BenchConfig& b, const std::vector<double>& t_s,
                                         const std::vector<double>& setpoint_deg, size_t rows) {
  ++t_strand->runs;
  Worker* w = t_worker;
  if (!w) {
    ++t_stats.groups;
    return simulate_bench(b, t_s, setpoint_deg, BenchSolver::closed_form, rows);
  }
  // a worker's run: asked for, and the scheduler resumes it with the result
  w->request = RunRequest{&b, &t_s, &setpoint_deg, rows};
  w->waiting = true;
  swapcontext(&w->ctx, &w->s->home);
  if (w->run_error) std::rethrow_exception(w->run_error);
  return std::move(w->out);
}

}  // namespace chainsim
