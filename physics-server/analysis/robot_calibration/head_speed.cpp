// A robot's speed from a run's trace (head_speed.h).
#include "analysis/robot_calibration/head_speed.h"

#include <cmath>
#include <stdexcept>

#include "model/units.h"
#include "output/run_reader.h"

namespace chainsim {

std::optional<Axis> pipe_axis(const Scene& scene) {
  const EnvironmentConfig& env = scene.world.environment;
  if (env.type != EnvironmentType::Pipe || env.pipe.segments.empty()) return std::nullopt;
  const PipeSegment& s0 = env.pipe.segments[0];
  if (s0.type != PipeSegment::Type::Straight) return std::nullopt;
  const double deg = kPi / 180;
  const double slope = (std::isnan(s0.slope_deg) ? env.pipe.slope_deg : s0.slope_deg) * deg;
  const double head = env.pipe.heading_deg * deg;
  return Axis{std::cos(slope) * std::cos(head), std::cos(slope) * std::sin(head), std::sin(slope)};
}

namespace {

// what the head's speed reads: the time and module 0's columns
bool head_column(const std::string& name) { return name == "t_s" || name.rfind("m0.", 0) == 0; }

double head_speed(RunReader& run, double t0_s, const std::optional<Axis>& axis) {
  const std::string file = run.dir() + "/trace.csv";
  const std::vector<std::string>& bodies = run.body_columns(0);
  if (bodies.empty()) throw std::runtime_error(file + ": no head position columns (m0.<body>.x, .y, .z)");
  const std::string body = bodies.front() + ".";  // the head's first body
  const std::vector<double>& t = run.trace_time();
  const std::vector<double>*px = run.trace_column(body + "x"), *py = run.trace_column(body + "y"),
                           *pz = run.trace_column(body + "z");
  double ta = NAN, tb = NAN, pa[3] = {0, 0, 0}, pb[3] = {0, 0, 0};
  for (size_t r = 0; r < t.size(); ++r) {
    if (t[r] + 1e-9 < t0_s) continue;
    const double p[3] = {(*px)[r], (*py)[r], (*pz)[r]};
    if (std::isnan(ta)) ta = t[r], pa[0] = p[0], pa[1] = p[1], pa[2] = p[2];
    tb = t[r], pb[0] = p[0], pb[1] = p[1], pb[2] = p[2];
  }
  if (std::isnan(ta) || !(tb > ta)) throw std::runtime_error(file + ": the run is shorter than the speed window");
  const double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  if (!std::isfinite(d[0]) || !std::isfinite(d[1]) || !std::isfinite(d[2]))
    throw std::runtime_error(file + ": the head's position is not finite in the speed window");
  double dir[3];
  if (axis) {
    for (int i = 0; i < 3; ++i) dir[i] = (*axis)[i];
  } else {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; ++i) dir[i] = n > 0 ? d[i] / n : 0;
  }
  return 100 * (d[0] * dir[0] + d[1] * dir[1] + d[2] * dir[2]) / (tb - ta);
}

}  // namespace

double head_speed_cm_s(const std::string& trace_csv_text, const std::string& run_dir, double t0_s,
                       const std::optional<Axis>& axis) {
  RunReader run = RunReader::from_text(run_dir, std::nullopt, trace_csv_text, {{}, head_column});
  return head_speed(run, t0_s, axis);
}

double head_speed_of_run(const std::string& run_dir, double t0_s, const std::optional<Axis>& axis) {
  RunReader run(run_dir, {{}, head_column});
  return head_speed(run, t0_s, axis);
}

}  // namespace chainsim
