// Robot-level speed tables (speed_table.h), read with the CSV reader.
#include "analysis/robot_calibration/speed_table.h"

#include <cmath>

#include "readers/csv_table.h"

namespace chainsim {

SpeedTable read_speed_table(const std::string& path) {
  const CsvTable tab = CsvTable::read_file(path, "the speed table", {{"real_speed_cm_s"}, {"paper_sim_speed_cm_s"}},
                                           {.comments = true});
  const int real = tab.column("real_speed_cm_s"), paper = tab.find("paper_sim_speed_cm_s");
  if (real == 0)
    tab.fail(tab.header_line(), 1, "the first column is the key (e.g. slope_deg), not real_speed_cm_s");
  SpeedTable t;
  t.key_name = tab.names()[0];
  for (size_t r = 0; r < tab.rows(); ++r) {
    SpeedRow row;
    row.key = tab.cell(r, 0).text;
    if (row.key.empty()) tab.fail_at(r, 0, "empty key");
    row.real = tab.number(r, real);
    row.paper = paper >= 0 && !tab.cell(r, paper).text.empty() ? tab.number(r, paper) : NAN;
    t.rows.push_back(row);
  }
  if (t.rows.size() < 2) tab.fail(tab.last_line(), 1, "at least 2 rows are needed");
  return t;
}

}  // namespace chainsim
