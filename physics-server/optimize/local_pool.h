// Local workers: up to N evaluations at once, each a chainsim-evaluate child
// process; tasks start in the order they were submitted.
#pragma once

#include <deque>
#include <list>
#include <memory>

#include "optimize/evaluator_pool.h"

namespace chainsim {

class LocalPool : public EvaluatorPool {
 public:
  LocalPool(const EvalContext& ctx, int workers);
  ~LocalPool() override;
  void submit(uint64_t id, const EvalTask& task) override;
  bool poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) override;
  size_t pending() const override { return queue_.size() + running_.size(); }
  int parallelism() const override { return workers_; }
  std::string describe() const override;

 private:
  EvalContext ctx_;
  int workers_;
  std::deque<std::pair<uint64_t, EvalTask>> queue_;
  std::list<std::pair<uint64_t, std::unique_ptr<Evaluation>>> running_;
};

}  // namespace chainsim
