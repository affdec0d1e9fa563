// Two fits at once on one core (paired_runs.h).
#include "analysis/calibration/paired_runs.h"

#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>

namespace chainsim {
namespace {

// a task's model run, waiting for the other task's
struct Request {
  const BenchConfig* b = nullptr;
  const std::vector<double>* t = nullptr;
  const std::vector<double>* sp = nullptr;
  size_t rows = 0;
  std::vector<BenchSample> out;
  std::exception_ptr error;
  bool done = false;
};

// The two workers share one mutex, held by whichever runs task code: a
// worker lets go of it only while it waits (for its run, or at its start),
// so the tasks' code never runs at the same time.
struct Pairing {
  std::mutex m;
  std::condition_variable cv;
  const std::vector<std::function<void()>>* tasks = nullptr;
  size_t next = 0;    // the next task to start
  size_t live = 0;    // workers still running tasks
  std::vector<Request*> waiting;
  std::exception_ptr error;
  int runs = 0;       // the runs the workers made, for the caller's count

  // every live worker waits for a run: the runs, on the same set-points
  // stepped together, then the workers woken
  void run_waiting() {
    while (!waiting.empty()) {
      std::vector<Request*> group, rest;
      for (Request* r : waiting) {
        const Request* g = group.empty() ? r : group.front();
        (r->t == g->t && r->sp == g->sp && r->b->dt_us == g->b->dt_us ? group : rest).push_back(r);
      }
      std::vector<const BenchConfig*> benches;
      std::vector<size_t> counts;
      for (const Request* r : group) benches.push_back(r->b), counts.push_back(r->rows);
      try {
        std::vector<std::vector<BenchSample>> outs =
            simulate_benches(benches, *group.front()->t, *group.front()->sp, BenchSolver::closed_form, counts);
        for (size_t i = 0; i < group.size(); ++i) group[i]->out = std::move(outs[i]);
      } catch (...) {
        for (Request* r : group) r->error = std::current_exception();
      }
      for (Request* r : group) r->done = true;
      waiting = std::move(rest);
    }
    cv.notify_all();
  }

  // a worker leaves (under m): the other may be waiting for a partner that
  // will not come
  void leave() {
    --live;
    if (live > 0 && waiting.size() == live) run_waiting();
  }
};

std::atomic<bool> g_paired{true};
thread_local Pairing* t_pairing = nullptr;
thread_local int t_runs = 0;

thread_local std::unique_lock<std::mutex>* t_lock = nullptr;

void work(Pairing& P) {
  std::unique_lock<std::mutex> lock(P.m);
  t_pairing = &P;
  t_lock = &lock;
  const int runs_before = t_runs;
  while (P.next < P.tasks->size() && !P.error) {
    const size_t i = P.next++;
    try {
      (*P.tasks)[i]();
    } catch (...) {
      if (!P.error) P.error = std::current_exception();
    }
  }
  P.runs += t_runs - runs_before;
  P.leave();
  t_pairing = nullptr;
  t_lock = nullptr;
}

}  // namespace

void set_paired_runs(bool on) { g_paired = on; }

void run_paired(const std::vector<std::function<void()>>& tasks) {
  size_t first = 0;   // the tasks before it have run
  auto rest_here = [&] {
    for (; first < tasks.size(); ++first) tasks[first]();
  };
  if (!g_paired) return rest_here();
  // inside a task whose partner still runs: one after the other (the task is
  // already paired), until the partner has ended
  while (first < tasks.size() && t_pairing && t_pairing->live > 1) tasks[first++]();
  if (tasks.size() - first < 2) return rest_here();
  Pairing P;
  P.tasks = &tasks;
  P.next = first;
  P.live = 2;
  std::thread a, b;
  try {
    a = std::thread([&P] { work(P); });
  } catch (const std::system_error&) {   // no thread to be had: one after the other, here
    return rest_here();
  }
  try {
    b = std::thread([&P] { work(P); });
  } catch (const std::system_error&) {   // the first worker runs them all
    std::unique_lock<std::mutex> lock(P.m);
    P.leave();
  }
  a.join();
  if (b.joinable()) b.join();
  t_runs += P.runs;
  if (P.error) std::rethrow_exception(P.error);
}

void run_paired_each(size_t n, const std::function<void(size_t)>& each) {
  std::vector<std::function<void()>> tasks;
  for (size_t i = 0; i < n; ++i) tasks.push_back([&each, i] { each(i); });
  run_paired(tasks);
}

int thread_model_runs() { return t_runs; }

std::vector<BenchSample> paired_simulate(const BenchConfig& b, const std::vector<double>& t_s,
                                         const std::vector<double>& setpoint_deg, size_t rows) {
  ++t_runs;
  if (!t_pairing) return simulate_bench(b, t_s, setpoint_deg, BenchSolver::closed_form, rows);
  Pairing& P = *t_pairing;
  Request r;
  r.b = &b;
  r.t = &t_s;
  r.sp = &setpoint_deg;
  r.rows = rows;
  P.waiting.push_back(&r);
  if (P.waiting.size() == P.live)
    P.run_waiting();
  else
    P.cv.wait(*t_lock, [&r] { return r.done; });
  if (r.error) std::rethrow_exception(r.error);
  return std::move(r.out);
}

}  // namespace chainsim
