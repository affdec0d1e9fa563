// The trace's columns and rows. See trace_writer.h.
#include "output/trace_writer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>

#include "text/number_text.h"
#include "model/units.h"

namespace chainsim {
namespace {

std::string make_header(const World& w, const std::vector<SensorColumn>& sensors, const std::vector<int>& first) {
  std::string out = "t_s";
  static const char* kBodyCols[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  for (int m = 0; m < w.module_count(); ++m) {
    const std::string pre = "m" + std::to_string(m) + ".";
    for (int b = 0; b < w.body_count(m); ++b)
      for (const char* c : kBodyCols) out += "," + pre + w.body_name(m, b) + "." + c;
    for (int s = 0; s < w.servo_count(m); ++s) {
      const std::string sp = pre + "s" + std::to_string(s) + ".";
      switch (w.servo_kind(m, s)) {
        case ServoKind::Rotary: out += "," + sp + "setpoint_deg," + sp + "angle_deg"; break;
        case ServoKind::Linear: out += "," + sp + "setpoint_mm," + sp + "position_mm"; break;
        case ServoKind::Screw: out += "," + sp + "command," + sp + "speed_mm_s"; break;
        case ServoKind::DcMotor: out += "," + sp + "command," + sp + "speed_rad_s"; break;
      }
      out += "," + sp + "current_a";
    }
    out += "," + pre + "supply_a";
    for (int k = 0; k < w.wheel_count(m); ++k) {
      const std::string wp = pre + w.wheel_name(m, k) + ".";
      out += "," + wp + "n_N," + wp + "f_N";
    }
    for (int k = first[m]; k < first[m + 1]; ++k) out += "," + sensors[k].name;
  }
  // docks as joints (physics.dock) only: what crosses each dock
  for (int d = 0; d < w.dock_count(); ++d) {
    const std::string dp = ",dock" + std::to_string(d) + ".";
    out += dp + "axial_N" + dp + "shear_N" + dp + "bend_Nm" + dp + "twist_Nm" + dp + "bend_deg";
  }
  out += "\n";
  return out;
}

// where each module's columns start in sensors (sorted by module), and the end
std::vector<int> first_columns(const std::vector<SensorColumn>& sensors, int modules) {
  std::vector<int> first(modules + 1, static_cast<int>(sensors.size()));
  for (int k = static_cast<int>(sensors.size()) - 1; k >= 0; --k)
    if (sensors[k].module < modules) first[sensors[k].module] = k;
  for (int m = modules - 1; m >= 0; --m) first[m] = std::min(first[m], first[m + 1]);
  return first;
}

// no allocation: a trace row is written in the step loop
void integer_field(std::string* out, int64_t v) {
  char buf[24];
  buf[0] = ',';
  const auto r = std::to_chars(buf + 1, buf + sizeof buf, v);
  out->append(buf, static_cast<size_t>(r.ptr - buf));
}

void field(std::string* out, double value, int decimals) {
  out->push_back(',');
  append_fixed(out, value, decimals);
}

}  // namespace

std::vector<SensorColumn> sensor_columns(const ChainModel& chain) {
  std::vector<SensorColumn> out;
  for (int m = 0; m < chain.size(); ++m) {
    const std::string pre = "m" + std::to_string(m) + ".";
    for (const SensorDef& sd : chain.modules[m].sensors) {
      const std::string p = pre + sd.name + ".";
      switch (sd.type) {
        case SensorType::MotorCurrent:
          out.push_back({m, SensorColumn::Source::Adc, sd.channel, p + "counts", sd.name});
          break;
        case SensorType::Accelerometer:
          for (int a = 0; a < 3; ++a)
            out.push_back({m, SensorColumn::Source::Adc, sd.channel + a, p + "xyz"[a] + "_counts", sd.name});
          break;
        case SensorType::Touch:
          if (sd.sectors <= 1) {
            out.push_back({m, SensorColumn::Source::DigitalIn, sd.channel, p + "in", sd.name});
            break;
          }
          for (int k = 0; k < sd.sectors; ++k)   // m<i>.<name>.<k>.in, sensor <name>.<k>
            out.push_back({m, SensorColumn::Source::DigitalIn, sd.channel + k, p + std::to_string(k) + ".in",
                           sd.name + "." + std::to_string(k)});
          break;
        case SensorType::WheelEncoder:
          out.push_back({m, SensorColumn::Source::Counter, sd.channel, p + "counts", sd.name});
          break;
      }
    }
  }
  return out;
}

TraceWriter::TraceWriter(const World& world, int64_t interval_us, std::vector<SensorColumn> sensors)
    : world_(world),
      sensors_(std::move(sensors)),
      first_sensor_(first_columns(sensors_, world.module_count())),
      header_(make_header(world, sensors_, first_sensor_)),
      interval_us_(interval_us) {}

int64_t TraceWriter::interval_for(const World& world, double trace_hz) {
  return std::max<int64_t>(world.dt_us(), std::llround(1e6 / trace_hz));
}

bool TraceWriter::row_due(std::string* row) {
  if (world_.time_us() < next_us_) return false;
  next_us_ += interval_us_;
  row->clear();
  append_row(row);
  return true;
}

void TraceWriter::append_row(std::string* out) const {
  const World& w = world_;
  append_seconds(out, w.time_us());
  for (int m = 0; m < w.module_count(); ++m) {
    for (int b = 0; b < w.body_count(m); ++b) {
      const World::BodyState s = w.body_state(m, b);
      for (int i = 0; i < 3; ++i) field(out, s.position[i], 6);
      for (int i = 0; i < 4; ++i) field(out, s.quaternion_wxyz[i], 6);
    }
    for (int s = 0; s < w.servo_count(m); ++s) {
      switch (w.servo_kind(m, s)) {
        case ServoKind::Rotary:
          field(out, w.servo_setpoint(m, s) * kDegPerRad, 4);
          field(out, w.servo_position(m, s) * kDegPerRad, 4);
          break;
        case ServoKind::Linear:
          field(out, w.servo_setpoint(m, s) * 1e3, 4);
          field(out, w.servo_position(m, s) * 1e3, 4);
          break;
        case ServoKind::Screw:
          field(out, w.servo_setpoint(m, s), 4);
          field(out, w.servo_rate(m, s) * 1e3, 4);
          break;
        case ServoKind::DcMotor:
          field(out, w.servo_setpoint(m, s), 4);
          field(out, w.servo_rate(m, s), 4);
          break;
      }
      field(out, w.servo_current_a(m, s), 5);
    }
    field(out, w.module_supply_current_a(m), 5);
    for (int k = 0; k < w.wheel_count(m); ++k) {
      const World::WheelState ws = w.wheel_state(m, k);
      field(out, ws.normal_n, 4);
      field(out, ws.across_n, 4);
    }
    if (first_sensor_[m] == first_sensor_[m + 1]) continue;
    ModuleSample s;  // what the firmware would read now (a pure read of the world)
    w.sample(m, &s);
    for (int k = first_sensor_[m]; k < first_sensor_[m + 1]; ++k) {
      const SensorColumn& c = sensors_[k];
      switch (c.source) {
        case SensorColumn::Source::Adc: integer_field(out, c.channel < 8 ? s.adc[c.channel] : 0); break;
        case SensorColumn::Source::DigitalIn: integer_field(out, (s.digital_in >> c.channel) & 1u); break;
        case SensorColumn::Source::Counter: integer_field(out, c.channel < 4 ? s.counter[c.channel] : 0); break;
      }
    }
  }
  for (int d = 0; d < w.dock_count(); ++d) {
    const World::DockForce f = w.dock_force(d);
    field(out, f.axial_n, 4);
    field(out, f.shear_n, 4);
    field(out, f.bend_nm, 6);
    field(out, f.twist_nm, 6);
    field(out, f.bend_deg, 3);
  }
  out->push_back('\n');
}

}  // namespace chainsim
