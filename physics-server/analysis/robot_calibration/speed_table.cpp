// Robot-level speed tables (speed_table.h), read with the CSV reader.
#include "analysis/robot_calibration/speed_table.h"

#include <cmath>
#include <map>

#include "readers/csv_table.h"
#include "readers/safe_text.h"

namespace chainsim {

SpeedTable read_speed_table(const std::string& path) {
  const CsvTable tab = CsvTable::read_file(path, "the speed table", {{"real_speed_cm_s"}, {"paper_sim_speed_cm_s"}},
                                           {.comments = true});
  const int real = tab.column("real_speed_cm_s"), paper = tab.find("paper_sim_speed_cm_s");
  if (real == 0)
    tab.fail(tab.header_line(), 1, "the first column is the key (e.g. slope_deg), not real_speed_cm_s");
  // each row is a run of the robot per candidate model: the rows bound calibrate's work
  if (tab.rows() > kMaxSpeedRows)
    tab.fail_at(kMaxSpeedRows, 0, "more than " + std::to_string(kMaxSpeedRows) + " rows (a run of the robot each)");
  SpeedTable t;
  t.key_name = tab.names()[0];
  std::map<std::string, size_t> seen;  // key -> its row
  const auto speed = [&](size_t r, int c) {
    const double v = tab.number(r, c);
    if (std::fabs(v) > kMaxSpeed_cm_s)
      tab.fail_at(r, c, tab.names()[static_cast<size_t>(c)] + " " + tab.cell(r, c).text + " is beyond +-" +
                            std::to_string(static_cast<int>(kMaxSpeed_cm_s)) + " cm/s");
    return v;
  };
  for (size_t r = 0; r < tab.rows(); ++r) {
    SpeedRow row;
    row.key = tab.cell(r, 0).text;
    if (row.key.empty()) tab.fail_at(r, 0, "empty key");
    // the key goes into a scene in place of {slope}: a short printable text
    if (row.key.size() > 32 || !is_printable_text(row.key))
      tab.fail_at(r, 0, "the key '" + shown_text_cut(row.key, 40) + "' is not a printable text of at most 32 bytes");
    if (const auto [it, fresh] = seen.emplace(row.key, r); !fresh)
      tab.fail_at(r, 0, "the key '" + row.key + "' is given twice (first at line " +
                            std::to_string(tab.row(it->second).line) + ")");
    row.real = speed(r, real);
    row.paper = paper >= 0 && !tab.cell(r, paper).text.empty() ? speed(r, paper) : NAN;
    t.rows.push_back(row);
  }
  if (t.rows.size() < 2) tab.fail(tab.last_line(), 1, "at least 2 rows are needed");
  return t;
}

}  // namespace chainsim
