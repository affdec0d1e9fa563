// How the chain as a whole moved, from the body poses in trace.csv: the
// `motion.*` metrics of the test files (docs/testing.md).
//
//   centroid   mean position of every body of every module (columns mK.<body>.x/y/z)
//   heading    direction from the tail to the head in the floor plane, unwrapped,
//              + = counterclockwise from above; head = the bodies of the first
//              max(1, n/4) modules, tail = those of the last max(1, n/4)
//   start/end  values averaged over the first 0.2 s / the last 1 s of the trace,
//              which averages out the wobble of a gait
//   axial/lateral  the centroid's path cut into 0.5 s windows, each window's
//              step split along / across the heading at the window's start
//              (+ lateral = to the chain's left), summed
//   twist      rotation of one body about its own long axis (local z), summed
//              row by row (right-hand about the head-ward axis)
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

class RunReader;

// a metric that does not exist (unknown: a mistake in the test file) or that
// cannot be computed for this run (e.g. a trace cut short by a fault)
struct MotionError : std::runtime_error {
  explicit MotionError(const std::string& what, bool unknown_name = false)
      : std::runtime_error(what), unknown(unknown_name) {}
  bool unknown;
};

struct ChainMotion {
  double dx_m = 0, dy_m = 0, dz_m = 0;  // centroid displacement, end - start
  double distance_m = 0;                // hypot(dx, dy)
  double heading_deg = 0;               // heading change, end - start
  double axial_m = 0, lateral_m = 0;    // centroid path along / across the heading
};

// the chain's motion over the whole trace; throws MotionError
ChainMotion chain_motion(RunReader& run);

// motion.<name> of a run: dx_m, dy_m, dz_m, distance_m, heading_deg, axial_m,
// lateral_m, or mK.<body>.twist_deg; throws MotionError naming the known ones
double motion_metric(RunReader& run, const std::string& name);

// the metric names motion_metric knows (twist as mK.<body>.twist_deg)
const std::vector<std::string>& motion_metric_names();

}  // namespace chainsim
