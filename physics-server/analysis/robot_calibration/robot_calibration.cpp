// Robot-level calibration (robot_calibration.h).
#include "analysis/robot_calibration/robot_calibration.h"

#include <chrono>
#include <filesystem>

#include "analysis/robot_calibration/robot_report.h"
#include "analysis/robot_calibration/scene_runner.h"
#include "analysis/robot_calibration/speed_table.h"

namespace chainsim {

void run_robot_calibration(const RobotCalibrationArgs& a, const RobotProgress& say) {
  const auto t_start = std::chrono::steady_clock::now();
  if (!(a.duration_s > a.window_start_s))
    throw RobotError("--duration (" + fmt_fixed(a.duration_s, 2) + " s) must exceed --window-start (" +
                     fmt_fixed(a.window_start_s, 2) + " s)");
  if (a.scene_template.find("{slope}") == std::string::npos)
    throw RobotError("--scene-template " + a.scene_template + ": needs {slope} (replaced by each row's key)");
  RobotReportInputs in;
  in.table = a.table;
  in.scene_template = a.scene_template;
  in.duration_s = a.duration_s;
  in.window_start_s = a.window_start_s;
  in.speeds = read_speed_table(a.table);
  std::vector<std::string> keys;
  for (const SpeedRow& r : in.speeds.rows) keys.push_back(r.key);
  const SceneVariants scenes(a.scene_template, keys);
  for (size_t k = 0; k < robot_knobs().size(); ++k) in.nominal.push_back(scenes.nominal(static_cast<int>(k)));
  in.usable = scenes.usable();

  std::error_code ec;
  std::filesystem::create_directories(a.out, ec);
  if (!std::filesystem::is_directory(a.out)) throw RobotError(a.out + ": cannot create the output directory");
  SceneRunOptions opt;
  opt.chainsim_exe = a.chainsim_exe;
  opt.firmware_dir = a.firmware_dir;
  opt.work_dir = std::filesystem::absolute(a.out).string() + "/runs";
  opt.duration_s = a.duration_s;
  opt.window_start_s = a.window_start_s;
  opt.jobs = a.jobs;
  SceneRunner runner(scenes, keys, opt);

  say("base: " + std::to_string(keys.size()) + " scenes, " + fmt_fixed(a.duration_s, 1) + " s each");
  const RobotSearch s = search_knobs(in.speeds.rows, in.usable,
                                     [&runner](const KnobSetting& st) { return runner.speeds(st); }, say);
  in.runs = runner.runs();
  in.settings = runner.settings();
  in.run_wall_s = runner.run_wall_s();
  in.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  write_robot_report(in, s, a.out);
  say("verdict " + s.verdict + ": gap " + fmt_fixed(s.gap_before) + " -> " + fmt_fixed(s.gap_after) +
      " cm/s; wrote " + a.out + "/report.json, report.md");
}

}  // namespace chainsim
