// `chainsim calibrate`: options in, the calibration libraries, exit codes out.
#include "chainsim/calibrate_command.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "analysis/calibration/calibration_report.h"
#include "analysis/calibration/servo_calibration.h"
#include "analysis/robot_calibration/robot_calibration.h"
#include "analysis/servo_bench/bench_config.h"
#include "readers/csv_table.h"

namespace chainsim {
namespace {

struct CalArgs {
  std::string bench, measured, out;
  bool quiet = false;
};

CalArgs g_calibrate_args;
RobotCalibrationArgs g_robot;

// progress lines on stderr with the wall time since the start
CalibrationProgress progress(bool quiet) {
  const auto t_start = std::chrono::steady_clock::now();
  return [quiet, t_start](const std::string& s) {
    if (quiet) return;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    std::fprintf(stderr, "chainsim calibrate [%6.1f s] %s\n", el, s.c_str());
  };
}

void make_out_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir)) throw ReportError(dir + ": cannot create the output directory");
}

int run_servo(const CalArgs& a) {
  const CalibrationProgress say = progress(a.quiet);
  const BenchConfig datasheet = a.bench.empty() ? BenchConfig{} : load_bench_config(a.bench);
  MeasuredRecord m = read_measured(a.measured, kMinMeasuredRows);
  make_out_dir(a.out);
  const ServoCalibration c = calibrate_servo(datasheet, std::move(m), say);
  write_calibration_report(c, a.bench, a.measured, a.out);
  say("wrote " + a.out + "/report.json, report.md, *.svg");
  return 0;
}

int run_robot(const CalArgs& a) {
  g_robot.out = a.out;
  std::error_code ec;
  g_robot.chainsim_exe = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  if (ec) throw RobotError("cannot find the chainsim executable (/proc/self/exe)");
  run_robot_calibration(g_robot, progress(a.quiet));
  return 0;
}

// runs one of the two; bad input or output: 1, anything else: 3
template <class Run>
int exit_code_of(Run run) {
  try {
    return run();
  } catch (const BenchError& e) {
    std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
  } catch (const CsvError& e) {
    std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
  } catch (const ReportError& e) {
    std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
  } catch (const RobotError& e) {
    std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim calibrate: internal error: %s\n", e.what());
    return 3;
  }
  return 1;
}

}  // namespace

Command add_calibrate_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "fit the servo model to a bench measurement (t_s,setpoint_deg,angle_deg[,current_a]) and find which "
      "catalogue effects it is missing (docs/calibration.md)");
  sub->add_option("--bench,-b", g_calibrate_args.bench, "bench file (datasheet values; docs/servo-bench.md)");
  auto* measured =
      sub->add_option("--measured,-m", g_calibrate_args.measured, "measured CSV: t_s,setpoint_deg,angle_deg[,current_a]");
  sub->add_option("--out,-o", g_calibrate_args.out, "output directory (report.json, report.md, SVG plots)")->required();
  sub->add_flag("--quiet,-q", g_calibrate_args.quiet, "print only errors");
  // robot level: a speed table and one scene per row (robot_calibration.h)
  auto* robot = sub->add_option("--robot", g_robot.table,
                                "robot-level table: key column (e.g. slope_deg), real_speed_cm_s"
                                "[,paper_sim_speed_cm_s] (instead of --measured)");
  auto* tmpl = sub->add_option("--scene-template", g_robot.scene_template,
                               "with --robot: scene file with {slope} replaced by each row's key");
  sub->add_option("--duration", g_robot.duration_s, "with --robot: simulated seconds per run (default 6)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--window-start", g_robot.window_start_s,
                  "with --robot: the speed is measured from this time to the end (default 1 s)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--jobs,-j", g_robot.jobs, "with --robot: runs at once (default 2)")->check(CLI::Range(1, 64));
  sub->add_option("--firmware-dir", g_robot.firmware_dir, "with --robot: where the fw-* programs are");
  measured->excludes(robot);
  robot->needs(tmpl);
  tmpl->needs(robot);
  // checked while parsing, so that it is a usage error
  sub->callback([measured, robot] {
    if (robot->count() == 0 && measured->count() == 0) throw CLI::RequiredError("--measured or --robot");
  });
  return {sub, [robot] {
            return robot->count() > 0 ? exit_code_of([] { return run_robot(g_calibrate_args); })
                                      : exit_code_of([] { return run_servo(g_calibrate_args); });
          }};
}


}  // namespace chainsim
