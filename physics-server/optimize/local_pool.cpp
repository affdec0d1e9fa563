#include "optimize/local_pool.h"

#include <signal.h>

#include <chrono>
#include <map>
#include <thread>

namespace chainsim {

namespace {

volatile sig_atomic_t g_interrupt = 0;

void on_signal(int sig) { g_interrupt = sig; }

}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interrupt_signal() { return g_interrupt; }

bool EvaluatorPool::evaluate(const std::vector<EvalTask>& tasks, std::vector<EvalResult>* results,
                             const std::function<void(size_t, const EvalResult&)>& on_done) {
  results->assign(tasks.size(), EvalResult{});
  // ids past anything a caller of submit() uses for its own tasks
  const uint64_t base = uint64_t{1} << 62;
  for (size_t i = 0; i < tasks.size(); ++i) submit(base + i, tasks[i]);
  size_t left = tasks.size();
  std::vector<std::pair<uint64_t, EvalResult>> done;
  while (left > 0) {
    done.clear();
    if (!poll(1.0, &done)) return false;
    for (auto& [id, r] : done) {
      const size_t i = static_cast<size_t>(id - base);
      (*results)[i] = std::move(r);
      --left;
      if (on_done) on_done(i, (*results)[i]);
    }
  }
  return true;
}

LocalPool::LocalPool(const EvalContext& ctx, int workers) : ctx_(ctx), workers_(workers < 1 ? 1 : workers) {}

LocalPool::~LocalPool() {
  for (auto& r : running_) r.second->terminate();
}

std::string LocalPool::describe() const {
  return std::to_string(workers_) + " local worker" + (workers_ == 1 ? "" : "s");
}

void LocalPool::submit(uint64_t id, const EvalTask& task) { queue_.emplace_back(id, task); }

bool LocalPool::poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_s);
  for (;;) {
    if (interrupt_signal()) {
      for (auto& r : running_) r.second->terminate();
      running_.clear();
      return false;
    }
    while (!queue_.empty() && static_cast<int>(running_.size()) < workers_) {
      running_.emplace_back(queue_.front().first, std::make_unique<Evaluation>(ctx_, queue_.front().second));
      queue_.pop_front();
    }
    bool any = false;
    for (auto it = running_.begin(); it != running_.end();) {
      if (it->second->poll()) {
        done->emplace_back(it->first, it->second->result());
        it = running_.erase(it);
        any = true;
      } else {
        ++it;
      }
    }
    if (any) {  // the freed workers take the next tasks before the caller looks
      while (!queue_.empty() && static_cast<int>(running_.size()) < workers_) {
        running_.emplace_back(queue_.front().first, std::make_unique<Evaluation>(ctx_, queue_.front().second));
        queue_.pop_front();
      }
      return true;
    }
    if (running_.empty() || std::chrono::steady_clock::now() >= until) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace chainsim
