// Ends a run when the scene's `stop_when` rules (scene.h, StopRule) say it
// has stopped mattering: a point of the chain whose furthest position has
// not grown by by_m in the last within_s, or that has not reached reach_m by
// by_s. Fed the positions of every trace row, so a rule and a search's
// measure (which reads trace.csv) see the same track.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "environment/pipe_progress.h"
#include "scene/scene.h"

namespace chainsim {

class EarlyStop {
 public:
  // pipe: the environment's pipe, needed by rules along the pipe (else null)
  EarlyStop(std::vector<StopRule> rules, std::shared_ptr<const PipeProgress> pipe);
  bool empty() const { return rules_.empty(); }
  // a trace row at t_us with the head's and tail's positions: true when the
  // run should end here; then why() says which rule and what it saw
  bool check(int64_t t_us, const Eigen::Vector3d& head, const Eigen::Vector3d& tail);
  const std::string& why() const { return why_; }
  const StopRule* rule() const { return fired_; }

 private:
  struct Track {
    double best = 0;                                // furthest position so far
    bool any = false;
    int64_t t0_us = 0;                              // the first row's time
    std::deque<std::pair<int64_t, double>> window;  // (time, best then), the oldest first
  };
  double position(const StopRule& r, const Eigen::Vector3d& p) const;

  std::vector<StopRule> rules_;
  std::shared_ptr<const PipeProgress> pipe_;
  std::vector<Track> tracks_;
  std::string why_;
  const StopRule* fired_ = nullptr;
};

}  // namespace chainsim
