// Bench files (bench_config.h), read with the strict YAML reader.
#include "analysis/servo_bench/bench_config.h"

#include "readers/strict_yaml.h"

namespace chainsim {
namespace {

StrictYaml bench_yaml(const std::string& file) {
  return StrictYaml(file, [](const std::string& message) { throw BenchError(message); });
}

// a number with lower bound lo (excluded when lo_open); absent: unchanged
void set(const StrictYaml& y, const YAML::Node& map, const std::string& path, const std::string& key, double lo,
         bool lo_open, double hi, double* out) {
  *out = y.number(map, key, *out, lo, hi, path, lo_open);
}

void load_servo(const StrictYaml& y, const YAML::Node& n, ServoParams* p) {
  const std::string s = "servo";
  y.keys(n, s,
         {"Kp", "Km", "Kt", "R", "L", "B", "J", "supply_v", "i_threshold_a", "coulomb_nm", "backlash_deg",
          "deadband_deg", "supply_sag_ohm", "pwm_frame_s", "current_limit_a", "pwm_frame_phase_s",
          "supply_sag_linear_ohm", "backlash_stiffness_nm_rad", "supply_rail_f",
          "pwm_pulse_s_per_deg", "deadband_comparator_deg"});
  set(y, n, s, "Kp", 0, false, 1e6, &p->kp);
  set(y, n, s, "Km", 0, false, 1e3, &p->km);
  set(y, n, s, "Kt", 0, false, 1e3, &p->kt);
  set(y, n, s, "R", 0, true, 1e6, &p->r);
  set(y, n, s, "L", 0, false, 10, &p->l);
  set(y, n, s, "B", 0, false, 1e3, &p->b);
  set(y, n, s, "J", 0, false, 1e3, &p->j);
  set(y, n, s, "supply_v", 0, false, 1e3, &p->supply_v);
  set(y, n, s, "i_threshold_a", 0, false, 1e3, &p->i_threshold_a);
  set(y, n, s, "coulomb_nm", 0, false, 1e3, &p->coulomb_nm);
  set(y, n, s, "backlash_deg", 0, false, 90, &p->backlash_deg);
  set(y, n, s, "deadband_deg", 0, false, 90, &p->deadband_deg);
  set(y, n, s, "supply_sag_ohm", 0, false, 1e6, &p->supply_sag_ohm);
  set(y, n, s, "pwm_frame_s", 0, false, 10, &p->pwm_frame_s);
  set(y, n, s, "current_limit_a", 0, false, 1e3, &p->current_limit_a);
  set(y, n, s, "pwm_frame_phase_s", 0, false, 10, &p->pwm_frame_phase_s);
  set(y, n, s, "supply_sag_linear_ohm", 0, false, 1e6, &p->supply_sag_linear_ohm);
  set(y, n, s, "backlash_stiffness_nm_rad", 0, false, 1e9, &p->backlash_stiffness_nm_rad);
  set(y, n, s, "supply_rail_f", 0, false, 10, &p->supply_rail_f);
  set(y, n, s, "pwm_pulse_s_per_deg", 0, false, kMaxPulseSPerDeg, &p->pwm_pulse_s_per_deg);
  set(y, n, s, "deadband_comparator_deg", 0, false, 90, &p->deadband_comparator_deg);
  if (const std::string why = servo_params_conflict(*p); !why.empty()) y.fail(n, "'servo': " + why);
}

}  // namespace

BenchConfig load_bench_text(const std::string& text, const std::string& file) {
  const StrictYaml y = bench_yaml(file);
  const YAML::Node root = y.parse(text);
  BenchConfig b;
  if (!root || root.IsNull()) return b;  // empty file: all defaults
  y.keys(root, "bench file", {"servo", "load", "sensors", "sim"});
  if (const YAML::Node n = root["servo"]; n && !n.IsNull()) load_servo(y, n, &b.servo);
  if (const YAML::Node n = root["load"]; n && !n.IsNull()) {
    y.keys(n, "load", {"inertia_kgm2", "torque_nm"});
    set(y, n, "load", "inertia_kgm2", 0, false, 1e3, &b.load_inertia_kgm2);
    set(y, n, "load", "torque_nm", -1e3, false, 1e3, &b.load_torque_nm);
  }
  if (const YAML::Node n = root["sensors"]; n && !n.IsNull()) {
    y.keys(n, "sensors", {"current_filter_tau_s"});
    set(y, n, "sensors", "current_filter_tau_s", 0, false, 100, &b.servo.current_filter_tau_s);
  }
  if (const YAML::Node n = root["sim"]; n && !n.IsNull()) {
    y.keys(n, "sim", {"dt_us"});
    b.dt_us = y.integer(n, "dt_us", b.dt_us, 1, 100000, "sim");
  }
  if (!(b.servo.j + b.load_inertia_kgm2 > 0)) {
    const YAML::Node n = root["load"] ? root["load"] : root;
    y.fail(n, "'servo.J' + 'load.inertia_kgm2' must be > 0 (something has to turn)");
  }
  return b;
}

BenchConfig load_bench_config(const std::string& file) {
  return load_bench_text(bench_yaml(file).read_file("the bench file"), file);
}

}  // namespace chainsim
