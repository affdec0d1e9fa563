// What one module's sensors read at a sample time, in the units its firmware
// gets them in: what its TickBegin carries.
#pragma once

#include <cstdint>

namespace chainsim {

struct ModuleSample {
  int n_servos = 0;
  // each driven actuator's position sensor, in that actuator's wire unit
  // (actuators/actuator.h): millidegrees (rotary servo: its potentiometer),
  // micrometres (linear servo: the slider), per mille (screw drive: it has no
  // sensor and echoes its command)
  int32_t servo_position_wire[4] = {};
  int n_adc = 0;
  uint16_t adc[8] = {};             // 10-bit counts
  uint16_t digital_in = 0;          // bit n = digital input n
  int n_counters = 0;
  int32_t counter[4] = {};
};

}  // namespace chainsim
