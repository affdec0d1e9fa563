// A robot's speed from a run's trace (head_speed.h).
#include "analysis/robot_calibration/head_speed.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "readers/csv_table.h"
#include "physics/units.h"

namespace chainsim {
namespace {


bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

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

double head_speed_cm_s(const std::string& trace_csv_text, const std::string& file, double t0_s,
                       const std::optional<Axis>& axis) {
  const CsvTable tab = CsvTable::parse(trace_csv_text, file, {{"t_s"}, {}});
  // the head's first body: the first position column after the time
  const std::string first = tab.names().size() > 1 ? tab.names()[1] : "";
  if (first.rfind("m0.", 0) != 0 || !ends_with(first, ".x"))
    throw std::runtime_error(file + ": no head position columns (m0.<body>.x, .y, .z)");
  const std::string body = first.substr(0, first.size() - 1);
  const int ct = tab.column("t_s"), cx = tab.find(body + "x"), cy = tab.find(body + "y"), cz = tab.find(body + "z");
  if (cy < 0 || cz < 0) throw std::runtime_error(file + ": no head position columns " + body + "y, " + body + "z");
  double ta = NAN, tb = NAN, pa[3] = {0, 0, 0}, pb[3] = {0, 0, 0};
  for (size_t r = 0; r < tab.rows(); ++r) {
    const double t = tab.number(r, ct);
    if (t + 1e-9 < t0_s) continue;
    const double p[3] = {tab.number(r, cx), tab.number(r, cy), tab.number(r, cz)};
    if (std::isnan(ta)) ta = t, pa[0] = p[0], pa[1] = p[1], pa[2] = p[2];
    tb = t, pb[0] = p[0], pb[1] = p[1], pb[2] = p[2];
  }
  if (std::isnan(ta) || !(tb > ta)) throw std::runtime_error(file + ": the run is shorter than the speed window");
  const double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  double dir[3];
  if (axis) {
    for (int i = 0; i < 3; ++i) dir[i] = (*axis)[i];
  } else {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; ++i) dir[i] = n > 0 ? d[i] / n : 0;
  }
  return 100 * (d[0] * dir[0] + d[1] * dir[1] + d[2] * dir[2]) / (tb - ta);
}

double head_speed_from_trace(const std::string& trace_csv, double t0_s, const std::optional<Axis>& axis) {
  std::ifstream in(trace_csv, std::ios::binary);
  if (!in) throw std::runtime_error(trace_csv + ": cannot read the run's trace");
  std::stringstream text;
  text << in.rdbuf();
  return head_speed_cm_s(text.str(), trace_csv, t0_s, axis);
}

}  // namespace chainsim
