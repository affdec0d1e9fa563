// A servo's set-point read from the pulses on its pin, as the servo reads
// them: the width of the latest complete pulse, while pulses keep coming.
#pragma once

#include <cstdint>

namespace chainsim::pic {

class ServoPulses {
 public:
  // pulses narrower or wider than this are glitches a servo ignores (cycles:
  // 0.5 ms and 2.5 ms at 5 MIPS)
  static constexpr uint64_t kMinWidthCycles = 2500;
  static constexpr uint64_t kMaxWidthCycles = 12500;
  // a servo without a pulse for this long goes limp (cycles: two 20 ms frames)
  static constexpr uint64_t kLimpAfterCycles = 200000;

  // the pin went high or low at cycle
  void edge(uint64_t cycle, bool high);
  // whether the servo is driven at cycle: a valid pulse began less than
  // kLimpAfterCycles ago
  bool driven(uint64_t cycle) const;
  // the latest valid pulse's width as a set-point in wire units
  // (millidegrees for a rotary servo: 1 cycle = 36)
  int32_t setpoint_wire() const { return setpoint_; }
  uint64_t pulses() const { return pulses_; }
  uint64_t glitches() const { return glitches_; }

  // the set-point a pulse of width cycles means: (width - 7500) x 36 mdeg,
  // the inverse of hal-pic's 7500 + cdeg x 5 / 18
  static int32_t wire_from_width(uint64_t width_cycles);

 private:
  bool high_ = false;
  bool seen_ = false;          // a valid pulse
  uint64_t rise_ = 0;          // cycle of the current pulse's rising edge
  uint64_t valid_rise_ = 0;    // rising edge of the latest valid pulse
  int32_t setpoint_ = 0;
  uint64_t pulses_ = 0, glitches_ = 0;
};

}  // namespace chainsim::pic
