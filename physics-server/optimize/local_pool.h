// Local workers: up to N evaluations at once, each a chainsim-evaluate child
// process; results collected by task index.
#pragma once

#include "optimize/evaluator_pool.h"

namespace chainsim {

class LocalPool : public EvaluatorPool {
 public:
  LocalPool(const EvalContext& ctx, int workers);
  bool evaluate(const std::vector<EvalTask>& tasks, std::vector<EvalResult>* results,
                const std::function<void(size_t, const EvalResult&)>& on_done) override;
  int parallelism() const override { return workers_; }
  std::string describe() const override;

 private:
  EvalContext ctx_;
  int workers_;
};

}  // namespace chainsim
