#include "optimize/local_pool.h"

#include <signal.h>

#include <chrono>
#include <list>
#include <memory>
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

LocalPool::LocalPool(const EvalContext& ctx, int workers) : ctx_(ctx), workers_(workers < 1 ? 1 : workers) {}

std::string LocalPool::describe() const {
  return std::to_string(workers_) + " local worker" + (workers_ == 1 ? "" : "s");
}

bool LocalPool::evaluate(const std::vector<EvalTask>& tasks, std::vector<EvalResult>* results,
                         const std::function<void(size_t, const EvalResult&)>& on_done) {
  results->assign(tasks.size(), EvalResult{});
  std::list<std::pair<size_t, std::unique_ptr<Evaluation>>> running;
  size_t next = 0, done = 0;
  while (done < tasks.size()) {
    if (interrupt_signal()) {
      for (auto& r : running) r.second->terminate();
      return false;
    }
    while (next < tasks.size() && static_cast<int>(running.size()) < workers_) {
      running.emplace_back(next, std::make_unique<Evaluation>(ctx_, tasks[next]));
      ++next;
    }
    bool any = false;
    for (auto it = running.begin(); it != running.end();) {
      if (it->second->poll()) {
        (*results)[it->first] = it->second->result();
        ++done;
        if (on_done) on_done(it->first, (*results)[it->first]);
        it = running.erase(it);
        any = true;
      } else {
        ++it;
      }
    }
    if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

}  // namespace chainsim
