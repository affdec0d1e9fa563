// The servo bench's CSV files (bench_csv.h).
#include "analysis/servo_bench/bench_csv.h"

#include <cmath>
#include <cstdio>

#include "readers/csv_table.h"

namespace chainsim {
namespace {

// fixed formatting; values within `zero` of 0 print as 0 (no "-0.0000")
void put(std::string* s, const char* fmt, double v, double zero) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, std::fabs(v) < zero ? 0.0 : v);
  *s += buf;
}

}  // namespace

SetpointProgram read_setpoints(const std::string& file) {
  const CsvTable tab = CsvTable::read_file(file, "the set-point file", {{"t_s", "setpoint_deg"}, {}});
  const int t = tab.column("t_s"), sp = tab.column("setpoint_deg");
  SetpointProgram p;
  for (size_t r = 0; r < tab.rows(); ++r) {
    const double tr = tab.number(r, t), spr = tab.number(r, sp);
    if (r > 0 && !(tr > p.t_s.back())) tab.fail_not_increasing(r, t);
    if (r > 0 && tr - p.t_s.front() > kMaxBenchSpan_s)
      tab.fail_at(r, t,
                  "the set-points span more than " + std::to_string(static_cast<int>(kMaxBenchSpan_s)) +
                      " s from the first row");
    p.t_s.push_back(tr);
    p.setpoint_deg.push_back(spr);
  }
  return p;
}

std::string format_bench_csv(const SetpointProgram& program, const std::vector<BenchSample>& samples) {
  std::string s = "t_s,setpoint_deg,angle_deg,current_a\n";
  s.reserve(program.t_s.size() * 40 + 64);
  for (size_t k = 0; k < program.t_s.size(); ++k) {
    put(&s, "%.6f", program.t_s[k], 5e-7);
    put(&s, ",%.4f", program.setpoint_deg[k], 5e-5);
    put(&s, ",%.4f", samples[k].angle_deg, 5e-5);
    put(&s, ",%.6f\n", samples[k].current_a, 5e-7);
  }
  return s;
}

}  // namespace chainsim
