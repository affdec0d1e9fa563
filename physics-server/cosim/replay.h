// A run's servo commands replayed into a fresh World with no processes: the
// physics alone, for `chainsim bench` (co-simulation vs physics-only speed).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace chainsim {

// one applied servo command of a run
struct ServoCommand {
  int64_t t_us;            // in force from this time
  int16_t module;
  int8_t servo;
  int8_t enabled;
  int32_t setpoint_wire;   // as the module sent it, in the actuator's wire unit
};

// replay commands (in time order) into a fresh world for the scene's duration;
// the trace's SHA-256 goes to trace_sha256 (may be null). Returns wall seconds.
double replay_physics(const Scene& scene, const std::vector<ServoCommand>& commands,
                      std::string* trace_sha256);

}  // namespace chainsim
