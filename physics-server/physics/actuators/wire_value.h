// The protocol carries every actuator value as an int32 in that actuator's
// wire unit (cs_tick_begin.servo_pos, cs_tick_end.servo_setpoint; each kind's
// file says its unit). This rounds a value already scaled to the wire unit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace chainsim {

// nearest int32 (halves away from zero), clamped to +-2147483647; not finite: 0
inline int32_t round_to_wire(double scaled) {
  if (!std::isfinite(scaled)) return 0;
  return static_cast<int32_t>(std::lround(std::clamp(scaled, -2147483647.0, 2147483647.0)));
}

}  // namespace chainsim
