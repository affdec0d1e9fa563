// Who evaluates: local worker processes (local_pool.h) or MPI ranks
// (mpi_pool.h). Tasks are submitted one by one under an id of the caller's
// and come back, as they finish, under that id: the search never sees which
// worker ran what, and keeps as many tasks queued as it has ready (several
// islands' generations at once).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "optimize/evaluation.h"

namespace chainsim {

class EvaluatorPool {
 public:
  virtual ~EvaluatorPool() = default;
  // queues a task; its result comes back from poll() under id
  virtual void submit(uint64_t id, const EvalTask& task) = 0;
  // runs the workers for up to wait_s seconds of wall time, or until at
  // least one task has finished; appends the finished ones to *done. false
  // when interrupted (SIGINT/SIGTERM): the running evaluations are ended and
  // the queue is left as it is.
  virtual bool poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) = 0;
  // tasks submitted and not yet handed back
  virtual size_t pending() const = 0;
  // how many evaluations run at once
  virtual int parallelism() const = 0;
  // "2 local workers", "2 MPI worker ranks"
  virtual std::string describe() const = 0;

  // a batch, blocking: (*results)[i] is tasks[i]'s; on_done(i, r) as each
  // ends. false when interrupted. Needs an idle pool (nothing pending).
  bool evaluate(const std::vector<EvalTask>& tasks, std::vector<EvalResult>* results,
                const std::function<void(size_t, const EvalResult&)>& on_done = nullptr);
};

// SIGINT and SIGTERM set a flag the pools and the search poll (they do not
// kill the process); call once from the command
void install_interrupt_handlers();
// the signal that asked to stop, or 0
int interrupt_signal();

}  // namespace chainsim
