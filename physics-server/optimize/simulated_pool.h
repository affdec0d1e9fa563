// A pool of N cores whose evaluations are not simulations: each task takes
// the wall time a real search measured for that individual (history.csv's
// wall_s, scaled), spent asleep in this process, and returns the result
// that search recorded. It is how the scheduler (the search's islands and
// queue) is measured at core counts this machine does not have: the busy
// fraction is the cores' busy time over N times the wall time (docs/benchmarks.md).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <queue>
#include <string>
#include <vector>

#include "optimize/evaluator_pool.h"
#include "optimize/history.h"

namespace chainsim {

class SimulatedPool : public EvaluatorPool {
 public:
  // recorded: a search's history (its simulated rows give each key's result
  // and wall time); scale: wall seconds slept per recorded second. A key
  // the history lacks gets the failed fitness and the recorded times' median.
  SimulatedPool(const std::vector<HistoryRow>& recorded, double failed_fitness, size_t n_measures, int cores,
                double scale);
  // times only: every key gets a wall time drawn from `times` by a hash of
  // the key, and a fitness drawn the same way, uniform in [0, 1) (a rugged
  // landscape: the scheduler, not the search, is what is measured)
  SimulatedPool(const std::vector<double>& times, size_t n_measures, int cores, double scale);
  void submit(uint64_t id, const EvalTask& task) override;
  bool poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) override;
  size_t pending() const override { return queue_.size() + running_.size(); }
  int parallelism() const override { return cores_; }
  std::string describe() const override;

  // since the first submit: wall seconds, and the cores' busy seconds (the
  // sleeps, as scheduled), in this process's time
  double wall_s() const;
  double busy_s() const { return busy_s_; }
  uint64_t evaluations() const { return evaluations_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Recorded {
    EvalResult result;
    double wall_s = 0;
  };
  struct Running {
    Clock::time_point end;
    uint64_t id;
    EvalResult result;
    bool operator>(const Running& o) const { return end > o.end || (end == o.end && id > o.id); }
  };
  void start_queued();

  std::map<std::string, Recorded> recorded_;
  std::vector<double> times_;  // times-only mode when not empty
  size_t n_measures_ = 0;
  EvalResult missing_;
  double missing_wall_s_ = 0;
  int cores_;
  double scale_;
  std::vector<std::pair<uint64_t, EvalTask>> queue_;  // FIFO (front at queue_head_)
  size_t queue_head_ = 0;
  std::priority_queue<Running, std::vector<Running>, std::greater<Running>> running_;
  bool started_ = false;
  Clock::time_point t0_;
  double busy_s_ = 0;
  uint64_t evaluations_ = 0;
};

}  // namespace chainsim
