// Robot-level calibration: runs a scene per row of a measured speed table
// (`chainsim run` processes: the same lockstep machinery, real module
// programs), measures the head's speed along the pipe axis, and fits a small
// robot-level catalogue of scene / module parameters with 1-D and 2-D
// searches. docs/calibration.md, "Robot-level calibration".
//
//   speed_table.h     the measured table (CSV)
//   robot_knobs.h     the catalogue, settings, RobotError
//   scene_variants.h  the row scenes, their nominal values and edited variants
//   scene_runner.h    the runs (ChildProcess) and their speeds (head_speed.h)
//   robot_fit.h       fits of the knob factors
//   robot_search.h    greedy rounds and the leave-one-row-out check
//   robot_report.h    report.json, report.md
#pragma once

#include <string>

#include "analysis/robot_calibration/robot_search.h"

namespace chainsim {

struct RobotCalibrationArgs {
  std::string table;            // the speed table
  std::string scene_template;   // scene file name with {slope} for each row's key
  std::string out;              // output directory (report.json, report.md, runs/)
  std::string chainsim_exe;     // the chainsim executable that runs the scenes
  std::string firmware_dir;     // where the fw-* programs are ("" = next to chainsim)
  double duration_s = 6;        // simulated seconds per run
  double window_start_s = 1;    // speed measured from here to the end of the run
  int jobs = 2;                 // runs at once
};

// the whole calibration: reads, runs, fits, writes the report; throws
// RobotError or CsvError for bad input, a failed run or an unwritable output
void run_robot_calibration(const RobotCalibrationArgs& a, const RobotProgress& say);

}  // namespace chainsim
