#include "cosim/early_stop.h"

#include <cmath>
#include <cstdio>

#include "scene/scene_stop.h"
#include "text/number_text.h"

namespace chainsim {

namespace {

// trace.csv writes positions to the micrometre: a mark missed by less than
// that may read as reached there, so only a clear miss stops the run
constexpr double kTraceResolutionM = 1e-6;

}  // namespace

EarlyStop::EarlyStop(std::vector<StopRule> rules, std::shared_ptr<const PipeProgress> pipe)
    : rules_(std::move(rules)), pipe_(std::move(pipe)), tracks_(rules_.size()) {}

double EarlyStop::position(const StopRule& r, const Eigen::Vector3d& p) const {
  if (r.along_pipe) return pipe_ ? pipe_->at(p) : 0.0;
  return r.axis.dot(p);
}

bool EarlyStop::check(int64_t t_us, const Eigen::Vector3d& head, const Eigen::Vector3d& tail) {
  for (size_t i = 0; i < rules_.size(); ++i) {
    const StopRule& r = rules_[i];
    Track& k = tracks_[i];
    const double x = position(r, r.tail ? tail : head);
    if (!k.any) {
      k.any = true;
      k.best = x;
      k.t0_us = t_us;
    } else if (x > k.best) {
      k.best = x;
    }
    const std::string who = std::string(r.tail ? "the tail" : "the head");
    const std::string along = r.along_pipe ? " along the pipe" : "";
    if (r.kind == StopRule::Kind::NoProgress) {
      const int64_t within_us = std::llround(r.within_s * 1e6);
      k.window.emplace_back(t_us, k.best);
      // the front: the last row at or before t - within
      while (k.window.size() > 1 && k.window[1].first <= t_us - within_us) k.window.pop_front();
      if (t_us - k.t0_us < within_us || k.window.front().first > t_us - within_us) continue;
      const double gained = k.best - k.window.front().second;
      if (gained < r.by_m) {
        why_ = "early stop at " + fixed_text(t_us * 1e-6, 3) + " s: " + who + " got " + fixed_text(gained * 1e3, 1) +
               " mm further" + along + " in the last " + general_text(r.within_s) + " s (" + stop_rule_text(r) + ")";
        fired_ = &r;
        return true;
      }
    } else {
      const int64_t by_us = std::llround(r.by_s * 1e6);
      if (t_us > by_us && k.best < r.reach_m - kTraceResolutionM) {
        why_ = "early stop at " + fixed_text(t_us * 1e-6, 3) + " s: " + who + " got no further than " +
               fixed_text(k.best, 4) + " m" + along + ", short of " + general_text(r.reach_m) + " m by " +
               general_text(r.by_s) + " s (" + stop_rule_text(r) + ")";
        fired_ = &r;
        return true;
      }
    }
  }
  return false;
}

}  // namespace chainsim
