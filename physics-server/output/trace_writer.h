// trace.csv: a header line naming every column, then one row per interval of
// simulated time, read from the World through its accessors. Fixed formats
// (text/number_text.h), so equal states give equal bytes: trace_sha256 in summary.json
// is compared across runs and versions.
//
// Columns: t_s, then per module m: each body's pose (m<m>.<body>.x, y, z in m;
// qw, qx, qy, qz body -> world), each driven actuator s (rotary:
// setpoint_deg, angle_deg; linear: setpoint_mm, position_mm; screw drive:
// command, speed_mm_s; DC motor: command, speed_rad_s; then current_a), the
// module's supply_a, then each wheel and pad on the wall (<name>.n_N: its
// normal force, .f_N: its friction across the wheel, a pad's magnitude; N),
// then each sensor of its module type, as its firmware reads it
// (World::sample): <sensor>.counts (motor current: ADC counts; wheel
// encoder: its counter), <sensor>.x_counts, .y_counts, .z_counts
// (accelerometer, ADC counts), <sensor>.in (touch: digital input, 0 or 1).
// After all modules, only when the docks are joints (physics.dock), per dock
// k: dock<k>.axial_N, shear_N, bend_Nm, twist_Nm, bend_deg (World::dock_force).
// docs/outputs.md lists them all.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/module_def.h"
#include "physics/chain_model.h"
#include "physics/world.h"

namespace chainsim {

// one sensor column of the trace: what a module's firmware reads on one
// ADC channel, digital input or counter
struct SensorColumn {
  enum class Source { Adc, DigitalIn, Counter };
  int module = 0;
  Source source = Source::Adc;
  int channel = 0;       // ADC channel, input bit or counter index
  std::string name;      // "m0.accel.x_counts"
  std::string sensor;    // its sensor's name in the module definition: "accel"
};

// the sensor columns of the chain (as the World is built from it)
std::vector<SensorColumn> sensor_columns(const ChainModel& chain);

class TraceWriter {
 public:
  // a row every interval_us of simulated time (at least one physics step),
  // the first at t = 0; sensors: the chain's sensor columns (sensor_columns)
  TraceWriter(const World& world, int64_t interval_us, std::vector<SensorColumn> sensors = {});
  // the interval of trace_hz rows per second on world
  static int64_t interval_for(const World& world, double trace_hz);

  const std::string& header() const { return header_; }  // newline included
  // true if a row is due at the world's time: then *row holds it (newline included)
  bool row_due(std::string* row);
  // the row of the world now, appended
  void append_row(std::string* out) const;

 private:
  const World& world_;
  std::vector<SensorColumn> sensors_;
  std::vector<int> first_sensor_;  // per module: index of its first column in sensors_ (size: modules + 1)
  std::string header_;
  int64_t interval_us_;
  int64_t next_us_ = 0;
};

}  // namespace chainsim
