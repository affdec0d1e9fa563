// The servo bench's CSV files: the set-point program it reads (t_s,
// setpoint_deg) and the record it writes (t_s, setpoint_deg, angle_deg,
// current_a). docs/servo-bench.md.
#pragma once

#include <string>
#include <vector>

#include "analysis/servo_bench/servo_stand.h"

namespace chainsim {

// longest set-point program accepted, simulated seconds
constexpr double kMaxBenchSpan_s = 10000.0;

struct SetpointProgram {
  std::vector<double> t_s;           // strictly increasing
  std::vector<double> setpoint_deg;
};

// reads a set-point CSV (columns by name, others ignored); throws CsvError
// ("file:line:column: what")
SetpointProgram read_setpoints(const std::string& file);

// the bench's output CSV: a header, then per row t_s (6 decimals),
// setpoint_deg and angle_deg (4), current_a (6); never "-0.0000"
std::string format_bench_csv(const SetpointProgram& program, const std::vector<BenchSample>& samples);

}  // namespace chainsim
