// The calibration's catalogue (effect_catalogue.h).
#include "analysis/calibration/effect_catalogue.h"

namespace chainsim {

const char* const kBaseNames[kNumBase] = {"Kp", "Km_Kt", "R", "load_inertia"};

const std::vector<Effect>& effect_catalogue() {
  static const std::vector<Effect> c = {
      {"static_friction_threshold", "i_threshold_a", &ServoParams::i_threshold_a, 1.0, 0.0, 0.2,
       {0.02, 0.05, 0.1}, {"hold", "step_onset"}},
      {"coulomb_friction", "torque_nm", &ServoParams::coulomb_nm, 1.0, 0.0, 0.03,
       {0.002, 0.005, 0.01}, {"braking", "hold"}},
      {"backlash", "width_deg", &ServoParams::backlash_deg, 1.0, 0.0, 10.0, {1.0, 2.5, 5.0},
       {"reversal", "braking"}},
      {"deadband", "width_deg", &ServoParams::deadband_deg, 1.0, 0.0, 10.0, {1.0, 2.5, 5.0},
       {"hold", "braking"}},
      {"supply_sag", "r_ohm", &ServoParams::supply_sag_ohm, 1.0, 0.0, 12.0, {1.0, 3.0, 6.0},
       {"high_current", "slewing"}},
      // the frame period is one of the usual servo frame rates (100, 60, 50,
      // 40, 30 Hz), not refined: the latch instants are piecewise constant in it
      {"pwm_frame_delay", "frame_ms", &ServoParams::pwm_frame_s, 1e-3, 0.0, 40.0,
       {10.0, 50.0 / 3, 20.0, 25.0, 100.0 / 3}, {"step_onset", "reversal"}, true},
      {"current_limit", "limit_a", &ServoParams::current_limit_a, 1.0, 0.03, 0.6, {0.1, 0.2, 0.3},
       {"high_current", "slewing"}},
  };
  return c;
}

BenchConfig model_config(const BenchConfig& datasheet, const std::vector<int>& effects,
                         const std::vector<double>& x) {
  BenchConfig b = datasheet;
  b.servo.kp *= x[0];
  b.servo.km *= x[1];
  b.servo.kt *= x[1];
  b.servo.r *= x[2];
  b.load_inertia_kgm2 *= x[3];
  for (size_t e = 0; e < effects.size(); ++e) {
    const Effect& ef = effect_catalogue()[effects[e]];
    b.servo.*(ef.member) = x[kNumBase + e] * ef.to_model;
  }
  return b;
}

std::vector<double> base_values(const BenchConfig& b) {
  return {b.servo.kp, b.servo.kt, b.servo.r, b.load_inertia_kgm2};
}

}  // namespace chainsim
