// A servo measurement to calibrate against: set-point, output angle and
// optionally the filtered current, sampled at increasing times
// (docs/calibration.md, "M.csv").
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace chainsim {

struct MeasuredRecord {
  std::vector<double> t, sp, angle, current;   // s, deg, deg, A
  bool has_current = false;
  size_t size() const { return t.size(); }
};

// reads t_s, setpoint_deg, angle_deg and the optional current_a (by name,
// other columns ignored) with at least min_rows rows; throws CsvError
// ("file:line:column: what")
MeasuredRecord read_measured(const std::string& file, size_t min_rows);

// what a measured record may hold: calibrate simulates its whole span once
// per candidate model, so the span and the rows bound its work. A record
// over them, or spanning less than a servo frame, is refused at its row.
constexpr size_t kMaxMeasuredRows = 200000;
constexpr double kMaxMeasuredSpan_s = 600.0;
constexpr double kMinMeasuredSpan_s = 0.02;
// a set-point or angle past two turns, or a current past 100 A, is no servo's
constexpr double kMaxMeasuredAngle_deg = 720.0;
constexpr double kMaxMeasuredCurrent_a = 100.0;

}  // namespace chainsim
