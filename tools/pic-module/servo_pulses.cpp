// A servo's set-point from its pulses. See servo_pulses.h.
#include "pic-module/servo_pulses.h"

#include "hal_pic_board.h"

namespace chainsim::pic {

int32_t ServoPulses::wire_from_width(uint64_t width_cycles) {
  // 1 cycle = 0.2 us = 18 / 5 cdeg = 36 mdeg
  return static_cast<int32_t>((static_cast<int64_t>(width_cycles) - HP_BOARD_SERVO_CENTER_CYCLES) * 36);
}

void ServoPulses::edge(uint64_t cycle, bool high) {
  if (high == high_) return;
  high_ = high;
  if (high) {
    rise_ = cycle;
    return;
  }
  const uint64_t width = cycle - rise_;
  if (width < kMinWidthCycles || width > kMaxWidthCycles) {
    ++glitches_;
    return;
  }
  ++pulses_;
  seen_ = true;
  valid_rise_ = rise_;
  setpoint_ = wire_from_width(width);
}

bool ServoPulses::driven(uint64_t cycle) const {
  return seen_ && cycle - valid_rise_ < kLimpAfterCycles;
}

}  // namespace chainsim::pic
