// The chip's busy time per step. See cpu_meter.h.
#include "pic-module/cpu_meter.h"

namespace chainsim::pic {

void CpuMeter::wait_entered(uint64_t now) {
  if (!started_) {
    started_ = true;
    s_.startup_cycles = busy_;
  } else {
    ++s_.steps;
    s_.busy_sum += busy_;
    s_.period_sum += now - step_start_;
    if (busy_ > s_.busy_worst) {
      s_.busy_worst = busy_;
      s_.worst_at = step_start_;
    }
  }
  step_start_ = now;
  busy_ = 0;
  over_ = false;
}

}  // namespace chainsim::pic
