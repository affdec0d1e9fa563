// A robot-level measurement: one row per condition (e.g. a pipe slope), the
// real robot's speed and optionally the paper's simulator's, in cm/s
// (scenes/measured/*.csv; docs/calibration.md, "Robot-level calibration").
#pragma once

#include <string>
#include <vector>

namespace chainsim {

struct SpeedRow {
  std::string key;       // the first column's text: what replaces {slope} in the scene template
  double real = 0;       // real_speed_cm_s
  double paper = 0;      // paper_sim_speed_cm_s; NaN when not given
};

struct SpeedTable {
  std::string key_name;  // the first column's name, e.g. slope_deg
  std::vector<SpeedRow> rows;
};

// reads the table: the key column first, real_speed_cm_s, optionally
// paper_sim_speed_cm_s (a blank cell is not given), '#' lines are comments;
// at least 2 rows. Throws CsvError ("file:line:column: what").
// A table of more than kMaxSpeedRows rows (each is a run of the robot per
// candidate model), a key given twice or longer than 32 bytes, or a speed
// beyond kMaxSpeed_cm_s is refused at its cell.
SpeedTable read_speed_table(const std::string& path);

constexpr size_t kMaxSpeedRows = 100;
constexpr double kMaxSpeed_cm_s = 1000.0;  // 10 m/s

}  // namespace chainsim
