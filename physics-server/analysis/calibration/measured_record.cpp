// Measured servo records (measured_record.h), read with the CSV reader.
#include "analysis/calibration/measured_record.h"

#include <cmath>

#include "readers/csv_table.h"

namespace chainsim {

MeasuredRecord read_measured(const std::string& file, size_t min_rows) {
  const CsvTable tab =
      CsvTable::read_file(file, "the measurement file", {{"t_s", "setpoint_deg", "angle_deg"}, {"current_a"}});
  MeasuredRecord m;
  m.has_current = tab.find("current_a") >= 0;
  const int cols[4] = {tab.column("t_s"), tab.column("setpoint_deg"), tab.column("angle_deg"),
                       tab.find("current_a")};
  std::vector<double>* dst[4] = {&m.t, &m.sp, &m.angle, &m.current};
  static const char* const kNames[4] = {"t_s", "setpoint_deg", "angle_deg", "current_a"};
  static constexpr double kBound[4] = {0, kMaxMeasuredAngle_deg, kMaxMeasuredAngle_deg, kMaxMeasuredCurrent_a};
  for (size_t r = 0; r < tab.rows(); ++r) {
    for (int c = 0; c < 4; ++c) {
      if (cols[c] < 0) continue;
      const double v = tab.number(r, cols[c]);
      if (c == 0 && r > 0 && !(v > m.t.back())) tab.fail_not_increasing(r, cols[c]);
      if (c == 0 && r > 0 && v - m.t.front() > kMaxMeasuredSpan_s)
        tab.fail_at(r, cols[c], "the record spans more than " + std::to_string(static_cast<int>(kMaxMeasuredSpan_s)) +
                                    " s from its first row (calibrate simulates the whole span for every candidate)");
      if (c == 0 && r >= kMaxMeasuredRows)
        tab.fail_at(r, cols[c], "more than " + std::to_string(kMaxMeasuredRows) + " rows");
      if (c > 0 && std::fabs(v) > kBound[c])
        tab.fail_at(r, cols[c], kNames[c] + std::string(" ") + tab.cell(r, cols[c]).text + " is beyond +-" +
                                    std::to_string(static_cast<int>(kBound[c])) + (c == 3 ? " A" : " degrees"));
      dst[c]->push_back(v);
    }
  }
  if (m.size() >= 2 && m.t.back() - m.t.front() < kMinMeasuredSpan_s)
    tab.fail(tab.last_line(), 1,
             "the record spans " + std::to_string(m.t.back() - m.t.front()) + " s: less than a servo frame (" +
                 std::to_string(kMinMeasuredSpan_s) + " s), nothing to fit");
  if (m.size() < min_rows)
    tab.fail(tab.last_line(), 1,
             "too few rows (" + std::to_string(m.size()) + "; at least " + std::to_string(min_rows) +
                 " needed for the cross-validation blocks)");
  return m;
}

}  // namespace chainsim
