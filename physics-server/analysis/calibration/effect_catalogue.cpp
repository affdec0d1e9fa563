// The calibration's catalogue (effect_catalogue.h).
#include "analysis/calibration/effect_catalogue.h"

#include <cmath>

namespace chainsim {

const char* const kBaseNames[kNumBase] = {"Kp", "Km_Kt", "R", "load_inertia"};

const std::vector<Effect>& effect_catalogue() {
  using P = ServoParams;
  static const std::vector<Effect> c = {
      {"static_friction_threshold", "", "no torque while |i| <= I_th",
       {{"i_threshold_a", &P::i_threshold_a, 1.0, 0.0, 0.2}},
       {{0.02}, {0.05}, {0.1}},
       {"hold", "step_onset"}},
      {"coulomb_friction", "", "output friction -Tc tanh(w / 0.005 rad/s)",
       {{"torque_nm", &P::coulomb_nm, 1.0, 0.0, 0.03}},
       {{0.002}, {0.005}, {0.01}},
       {"braking", "hold"}},
      {"backlash", "rigid", "gear play, rigid mesh: plastic closing",
       {{"width_deg", &P::backlash_deg, 1.0, 0.0, 10.0}},
       {{1.0}, {2.5}, {5.0}},
       {"reversal", "braking"}},
      // the mesh stiffness spans soft couplings (resonance ~100 Hz) to the
      // rigid limit (~10 kHz at the 100 us fit step), on a log scale
      {"backlash", "compliant", "gear play, compliant mesh: spring k, damper 2 sqrt(k J)",
       {{"width_deg", &P::backlash_deg, 1.0, 0.0, 10.0},
        {"stiffness_nm_rad", &P::backlash_stiffness_nm_rad, 1.0, 0.05, 1000.0, true}},
       {{1.0, 3.0}, {2.5, 3.0}, {5.0, 3.0}, {2.5, 100.0}},
       {"reversal", "braking"}},
      {"deadband", "dead_zone", "the amplifier ignores errors within +-width/2 (the band subtracted)",
       {{"width_deg", &P::deadband_deg, 1.0, 0.0, 10.0}},
       {{1.0}, {2.5}, {5.0}},
       {"hold", "braking"}},
      // an analogue servo's window comparator gates the amplifier: the same
      // window, but the whole error drives outside it
      {"deadband", "comparator", "no drive within +-width/2, the whole error outside (window comparator)",
       {{"width_deg", &P::deadband_comparator_deg, 1.0, 0.0, 10.0}},
       {{1.0}, {2.5}, {5.0}},
       {"hold", "braking"}},
      {"supply_sag", "pwm_bridge", "PWM bridge: drive = duty x (Vs - Rs |i|)",
       {{"r_ohm", &P::supply_sag_ohm, 1.0, 0.0, 12.0}},
       {{1.0}, {3.0}, {6.0}},
       {"high_current", "slewing"}},
      {"supply_sag", "linear_driver", "linear driver: gain kept, limit Vs - Rs |i|",
       {{"r_ohm", &P::supply_sag_linear_ohm, 1.0, 0.0, 12.0}},
       {{1.0}, {3.0}, {6.0}},
       {"high_current", "slewing"}},
      // either driver fed from a rail capacitor that the supply charges
      // through Rs (the sag lags the draw by Rs C; a bridge's braking returns
      // current to the rail); C from 1 uF (no lag at the 100 us fit step) to
      // 20 mF, on a log scale; each refines the form without the capacitor
      {"supply_sag", "pwm_bridge_rail",
       "PWM bridge on a rail capacitor: drive = duty x V, C dV/dt = (Vs - V)/Rs - duty i",
       {{"r_ohm", &P::supply_sag_ohm, 1.0, 0.0, 12.0}, {"rail_uf", &P::supply_rail_f, 1e-6, 1.0, 20000.0, true}},
       {{3.0, 100.0}, {3.0, 1000.0}},
       {"high_current", "slewing"},
       EffectFit::smooth,
       "pwm_bridge"},
      {"supply_sag", "linear_driver_rail", "linear driver on a rail capacitor: limit V, C dV/dt = (Vs - V)/Rs - |i|",
       {{"r_ohm", &P::supply_sag_linear_ohm, 1.0, 0.0, 12.0}, {"rail_uf", &P::supply_rail_f, 1e-6, 1.0, 20000.0, true}},
       {{3.0, 100.0}, {3.0, 1000.0}},
       {"high_current", "slewing"},
       EffectFit::smooth,
       "linear_driver"},
      // period and phase come from the delays of the set-point changes
      {"pwm_frame_delay", "at_frame", "set-point latched at frames: phase + n x period",
       {{"frame_ms", &P::pwm_frame_s, 1e-3, 2.5, 40.0}, {"phase_ms", &P::pwm_frame_phase_s, 1e-3, 0.0, 40.0}},
       {},
       {"step_onset", "reversal"},
       EffectFit::frame_clock},
      // an RC servo's decoder acts at the pulse's falling edge, and the pulse
      // is 1.5 ms + k (sp - 90 deg) wide: the delay depends on the set-point
      // too. k from 1 us/deg to 25 us/deg spans the usual conventions (1-2 ms
      // over 180 deg: 5.6; 0.5-2.5 ms over 180 deg or 1-2 ms over 90 deg:
      // 11.1). Refines the form above (from its clock and from its own clocks,
      // servo_fit.cpp)
      {"pwm_frame_delay", "falling_edge",
       "set-point sent as a pulse 1.5 ms + k (sp - 90 deg) wide at frames phase + n x period, acting at its falling "
       "edge",
       {{"frame_ms", &P::pwm_frame_s, 1e-3, 2.5, 40.0},
        {"phase_ms", &P::pwm_frame_phase_s, 1e-3, 0.0, 40.0},
        {"pulse_us_per_deg", &P::pwm_pulse_s_per_deg, 1e-6, 1.0, 25.0}},
       {},
       {"step_onset", "reversal"},
       EffectFit::frame_clock,
       "at_frame"},
      {"current_limit", "", "drive limited to Km w +- R I_lim",
       {{"limit_a", &P::current_limit_a, 1.0, 0.03, 0.6}},
       {{0.1}, {0.2}, {0.3}},
       {"high_current", "slewing"}},
  };
  return c;
}

std::vector<int> effect_variants(const std::string& name) {
  std::vector<int> out;
  for (size_t e = 0; e < effect_catalogue().size(); ++e)
    if (name == effect_catalogue()[e].name) out.push_back(static_cast<int>(e));
  return out;
}

size_t param_count(const std::vector<int>& effects) { return param_offset(effects, effects.size()); }

size_t param_offset(const std::vector<int>& effects, size_t e) {
  size_t n = kNumBase;
  for (size_t i = 0; i < e; ++i) n += effect_catalogue()[effects[i]].params.size();
  return n;
}

BenchConfig model_config(const BenchConfig& datasheet, const std::vector<int>& effects,
                         const std::vector<double>& x) {
  BenchConfig b = datasheet;
  b.servo.kp *= x[0];
  b.servo.km *= x[1];
  b.servo.kt *= x[1];
  b.servo.r *= x[2];
  b.load_inertia_kgm2 *= x[3];
  size_t i = kNumBase;
  for (int e : effects)
    for (const EffectParam& q : effect_catalogue()[e].params) b.servo.*(q.member) = x[i++] * q.to_model;
  return b;
}

std::vector<double> base_values(const BenchConfig& b) {
  return {b.servo.kp, b.servo.kt, b.servo.r, b.load_inertia_kgm2};
}

}  // namespace chainsim
