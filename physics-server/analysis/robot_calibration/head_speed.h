// A robot's speed from a run: how fast the head module's first body moves
// along the pipe's axis over a window at the end of the run (trace.csv of
// `chainsim run`).
#pragma once

#include <array>
#include <optional>
#include <string>

#include "scene/scene.h"

namespace chainsim {

using Axis = std::array<double, 3>;   // a unit vector, world frame

// the unit vector of the pipe's first segment when the scene is a pipe
// whose first segment is straight (its slope and heading); else nothing
std::optional<Axis> pipe_axis(const Scene& scene);

// the speed in cm/s of the head's first body (the trace's columns
// m0.<body>.x, .y, .z) from the first row at or after t0_s to the last row,
// along `axis`, or along its own displacement when there is none. The trace
// is read by the run reader (output/run_reader.h). Throws RunReadError for a
// missing or malformed trace, std::runtime_error when it has no head
// position or ends before the window has two rows.
double head_speed_of_run(const std::string& run_dir, double t0_s, const std::optional<Axis>& axis);
// the same from trace.csv's text; run_dir names it in messages
double head_speed_cm_s(const std::string& trace_csv_text, const std::string& run_dir, double t0_s,
                       const std::optional<Axis>& axis);

}  // namespace chainsim
