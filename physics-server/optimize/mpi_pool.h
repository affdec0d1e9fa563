// MPI mode (`mpirun -np K chainsim optimize ...`): rank 0 runs the search and
// hands evaluations to ranks 1..K-1, each of which runs them as local
// chainsim-evaluate children and sends the results back. Tasks and results are
// small JSON messages; every rank loads the problem file itself.
//
// A rank that dies: with OpenMPI 4.1 mpirun ends the whole job when a rank
// dies, unless it was started with `--enable-recovery --mca
// orte_abort_on_non_zero_status 0` (docs/optimize.md). With those, rank 0
// notices (a rank on its own host: its process is gone; any rank: no message
// for rank_timeout_s while it holds work), names it, and gives its
// evaluations to the others. MPI_Finalize can hang once a rank has died, so
// then every rank leaves without it, after its outputs are written.
#pragma once

#include <memory>
#include <string>

#include "optimize/evaluator_pool.h"

namespace chainsim {

// true when started by mpirun (OpenMPI's OMPI_COMM_WORLD_SIZE), a PMI launcher (PMI_SIZE) or a PMIx one (PMIX_RANK: srun --mpi=pmix)
bool launched_by_mpirun();

class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  // true when mpirun keeps the job alive after a rank dies (--enable-recovery
  // and orte_abort_on_non_zero_status 0)
  static bool recovery_enabled();
  // true when mpirun would exit 0 whatever its ranks exit with (either
  // option): rank 0 then ends its mpirun with SIGTERM after a failed search,
  // so that it does not look done
  static bool exit_status_ignored();
  // ends this process: MPI_Finalize, or (once a rank was lost) an exit
  // without it. remote_lost: a rank on another host was lost; mpirun, with
  // the recovery options, can then wait for ever after rank 0 has gone, so
  // rank 0 ends the job with MPI_Abort (error code 0 when the search finished)
  [[noreturn]] void exit(int code, bool rank_lost, bool remote_lost = false);

 private:
  int rank_ = 0, size_ = 1;
};

// rank 0's side: the worker ranks as an evaluator pool
class MpiPool : public EvaluatorPool {
 public:
  // size: MPI_COMM_WORLD's; rank_timeout_s: silence after which a rank
  // holding work is given up
  MpiPool(int size, double rank_timeout_s, bool quiet);
  ~MpiPool() override;
  void submit(uint64_t id, const EvalTask& task) override;
  bool poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) override;
  size_t pending() const override;
  int parallelism() const override;
  std::string describe() const override;
  // ranks given up so far, and of those the ones on another host than rank 0
  int lost_ranks() const;
  int lost_remote_ranks() const;
  // tells every live worker rank to end (finalize = whether they may call MPI_Finalize)
  void stop_workers(bool finalize);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ranks 1..K-1: run what rank 0 sends, `workers` at a time, until it says
// stop. Returns the exit code; *finalize says whether MPI_Finalize is safe.
int mpi_worker_main(const EvalContext& ctx, int rank, int workers, double rank_timeout_s, bool* finalize);

}  // namespace chainsim
