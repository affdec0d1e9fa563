// Robot-level calibration (`chainsim calibrate --robot T.csv --scene-template
// S-{slope}.yaml --out DIR`): runs a scene per row of a measured speed table
// (as `chainsim run` processes: the same lockstep machinery, real module
// programs), measures the head's speed along the pipe axis, and fits a small
// robot-level catalogue of scene / module parameters (screw drive thrust and
// free speed, grip torque of the support arms, module-pipe friction) with
// 1-D and 2-D searches. docs/calibration.md, "Robot-level calibration".
#pragma once

#include <stdexcept>
#include <string>

namespace chainsim {
namespace robotcal {

struct RobotError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RobotArgs {
  std::string table, scene_template, out, firmware_dir;
  double duration_s = 6;     // simulated seconds per run
  double window_start_s = 1; // speed measured from here to the end of the run
  int jobs = 2;              // runs at once
  bool quiet = false;
};

// run the calibration; writes DIR/report.json and report.md; returns the exit code
int run_robot(const RobotArgs& a);

}  // namespace robotcal
}  // namespace chainsim
