// Who evaluates a generation: local worker processes (local_pool.h) or MPI
// ranks (mpi_pool.h). Either runs the tasks of a batch in parallel and hands
// the results back by task index, so the search never sees which worker ran
// what or in which order they finished.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "optimize/evaluation.h"

namespace chainsim {

class EvaluatorPool {
 public:
  virtual ~EvaluatorPool() = default;
  // evaluates every task; (*results)[i] is task i's result. on_done(i, r) is
  // called as each ends (progress, the journal). false when interrupted
  // (SIGINT/SIGTERM): the results are then incomplete.
  virtual bool evaluate(const std::vector<EvalTask>& tasks, std::vector<EvalResult>* results,
                        const std::function<void(size_t, const EvalResult&)>& on_done) = 0;
  // how many evaluations run at once
  virtual int parallelism() const = 0;
  // "2 local workers", "2 MPI worker ranks"
  virtual std::string describe() const = 0;
};

// SIGINT and SIGTERM set a flag the pools and the search poll (and no longer
// kill the process); call once from the command
void install_interrupt_handlers();
// the signal that asked to stop, or 0
int interrupt_signal();

}  // namespace chainsim
