#include "optimize/simulated_pool.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace chainsim {

SimulatedPool::SimulatedPool(const std::vector<HistoryRow>& recorded, double failed_fitness, size_t n_measures,
                             int cores, double scale)
    : cores_(std::max(1, cores)), scale_(scale) {
  std::vector<double> walls;
  for (const HistoryRow& r : recorded) {
    if (r.cached || recorded_.count(r.genome)) continue;
    recorded_[r.genome] = {r.result, r.result.wall_s};
    walls.push_back(r.result.wall_s);
  }
  if (!walls.empty()) {
    std::sort(walls.begin(), walls.end());
    missing_wall_s_ = walls[walls.size() / 2];
  }
  missing_.fitness = failed_fitness;
  missing_.measures.assign(n_measures, std::nan(""));
  missing_.failed = true;
  missing_.why = "not in the recorded history";
}

SimulatedPool::SimulatedPool(const std::vector<double>& times, size_t n_measures, int cores, double scale)
    : times_(times), n_measures_(n_measures), cores_(std::max(1, cores)), scale_(scale) {}

std::string SimulatedPool::describe() const {
  return std::to_string(cores_) + " simulated cores";
}

double SimulatedPool::wall_s() const {
  return started_ ? std::chrono::duration<double>(Clock::now() - t0_).count() : 0.0;
}

void SimulatedPool::submit(uint64_t id, const EvalTask& task) {
  if (!started_) {
    started_ = true;
    t0_ = Clock::now();
  }
  queue_.emplace_back(id, task);
  start_queued();
}

void SimulatedPool::start_queued() {
  const Clock::time_point now = Clock::now();
  while (queue_head_ < queue_.size() && static_cast<int>(running_.size()) < cores_) {
    const auto& [id, task] = queue_[queue_head_++];
    double wall = missing_wall_s_;
    EvalResult r = missing_;
    if (!times_.empty()) {
      uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a of the key
      for (unsigned char c : task.key) h = (h ^ c) * 0x100000001b3ull;
      wall = times_[h % times_.size()];
      r = EvalResult{};
      r.fitness = static_cast<double>((h * 0x9E3779B97F4A7C15ull) >> 11) * 0x1.0p-53;
      r.measures.assign(n_measures_, r.fitness);
    } else if (const auto it = recorded_.find(task.key); it != recorded_.end()) {
      wall = it->second.wall_s;
      r = it->second.result;
    }
    r.wall_s = wall;
    const double sleep = wall * scale_;
    busy_s_ += sleep;
    ++evaluations_;
    running_.push({now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(sleep)), id, r});
  }
  if (queue_head_ == queue_.size()) {
    queue_.clear();
    queue_head_ = 0;
  }
}

bool SimulatedPool::poll(double wait_s, std::vector<std::pair<uint64_t, EvalResult>>* done) {
  if (interrupt_signal()) return false;
  const Clock::time_point until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wait_s));
  if (running_.empty()) return true;
  const Clock::time_point next = running_.top().end;
  std::this_thread::sleep_until(std::min(next, until));
  const Clock::time_point now = Clock::now();
  while (!running_.empty() && running_.top().end <= now) {
    done->emplace_back(running_.top().id, running_.top().result);
    running_.pop();
  }
  start_queued();
  return true;
}

}  // namespace chainsim
