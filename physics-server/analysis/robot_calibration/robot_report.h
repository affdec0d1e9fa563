// The robot calibration's report: DIR/report.json and DIR/report.md.
// docs/calibration.md, "Robot-level calibration".
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "analysis/robot_calibration/robot_search.h"

namespace chainsim {

// what the report says besides the search's results
struct RobotReportInputs {
  std::string table, scene_template;   // as given
  SpeedTable speeds;                   // the measured table
  std::vector<double> nominal;         // per knob id
  std::vector<int> usable;             // knobs that applied
  double duration_s = 0, window_start_s = 0;
  int runs = 0;                        // processes run
  size_t settings = 0;                 // settings evaluated
  double run_wall_s = 0, wall_s = 0;
};

nlohmann::ordered_json robot_report_json(const RobotReportInputs& in, const RobotSearch& s);
std::string robot_report_md(const RobotReportInputs& in, const RobotSearch& s, const nlohmann::ordered_json& j);

// writes both to out_dir; throws RobotError
void write_robot_report(const RobotReportInputs& in, const RobotSearch& s, const std::string& out_dir);

}  // namespace chainsim
