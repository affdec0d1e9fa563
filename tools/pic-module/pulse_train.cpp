// Encoder pulses. See pulse_train.h.
#include "pic-module/pulse_train.h"

#include <algorithm>
#include <cstdlib>

namespace chainsim::pic {

void PulseTrain::tick(int32_t count, uint64_t from, uint64_t span) {
  if (!started_) {  // the count before the first tick is where the encoder stood
    started_ = true;
    last_ = count;
    return;
  }
  const uint64_t n = static_cast<uint64_t>(std::llabs(static_cast<long long>(count) - last_));
  last_ = count;
  if (n == 0) return;
  owed_ += n;
  half_ = std::max<uint64_t>(kMinHalfPeriod, span / (2 * owed_));
  if (next_ == kNever) next_ = from + (high_ ? 0 : half_ / 2);
}

void PulseTrain::act(uint64_t cycle) {
  if (cycle < next_ || next_ == kNever) return;
  if (high_) {
    high_ = false;
    ++sent_;
    --owed_;
  } else {
    high_ = true;
  }
  next_ = (high_ || owed_ > 0) ? cycle + half_ : kNever;
}

}  // namespace chainsim::pic
