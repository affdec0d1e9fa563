// The parameters of the paper's DC servomotor model (section 3.2, Table 1)
// and of the effects calibration may add to it: data, read from module files
// (ActuatorDef::servo) and scenes (WorldConfig::servo), below physics/. The
// equations, and what each effect does: physics/actuators/servo_model.h.
#pragma once

namespace chainsim {

struct ServoParams {
  double kp = 12.0;        // V/rad
  double km = 0.14;        // V/(rad/s)
  double kt = 0.14;        // N m/A
  double r = 12.0;         // ohm
  double l = 0.0075;       // H
  double b = 3.5e-6;       // N m/(rad/s)
  double j = 7.0e-7;       // kg m^2, referred to the output shaft
  double supply_v = 5.0;   // V
  double current_filter_tau_s = 0.003;
  // static-friction current threshold, A: no torque for |i| <= it (servo_model.h); 0 = off
  double i_threshold_a = 0.0;
  // effect catalogue (servo_model.h); 0 = off for each
  double coulomb_nm = 0.0;       // coulomb_friction: torque, N m
  double backlash_deg = 0.0;     // backlash: total play, degrees of output
  double deadband_deg = 0.0;     // deadband: total width of the error dead band, degrees
  double supply_sag_ohm = 0.0;   // supply_sag: supply internal resistance, ohm
  double pwm_frame_s = 0.0;      // pwm_frame_delay: set-point frame period, s (50 Hz = 0.02)
  double current_limit_a = 0.0;  // current_limit: driver current limit, A
  // variants and extra parameters of the catalogue's effects (servo_model.h); 0 = as without them
  double pwm_frame_phase_s = 0.0;          // pwm_frame_delay: time of the first frame after reset, s
  double supply_sag_linear_ohm = 0.0;      // supply_sag, linear driver: Rs, ohm (limit Vs - Rs |i|)
  double backlash_stiffness_nm_rad = 0.0;  // backlash, compliant mesh: N m/rad (0 = rigid, plastic closing)
  double supply_rail_f = 0.0;              // supply_sag, rail variant: the rail capacitor, F (0 = none)
  // pwm_frame_delay, falling-edge variant: the pulse's width per degree of
  // set-point, s/deg (1.5 ms at 90 deg); the set-point then acts at the
  // pulse's falling edge (0 = at the frame itself)
  double pwm_pulse_s_per_deg = 0.0;
  // deadband, comparator form: total width, degrees; inside no drive, outside
  // the whole error drives (an analogue servo's window comparator); 0 = off
  double deadband_comparator_deg = 0.0;
  // ... and the set-point (deg on the pulse's scale, where 90 is the 1.5 ms
  // centre) at the model's set-point 0: in a module the joint angle 0 is the
  // servo's centre, hence 90; the servo bench sets its first row's
  // (servo_stand.cpp), its set-points being relative to it
  double pwm_pulse_origin_deg = 90.0;
  // Current sense chain (our assumption, the paper gives no figures): a 1 ohm
  // shunt, an amplifier of gain 10 and a 10-bit ADC with a 5 V reference:
  // 1023 counts = 0.5 A (0.489 mA per count). The stall current is
  // Vs/R = 0.417 A = 853 counts, so the full range is used with headroom.
  double adc_full_scale_a = 0.5;
};

// An RC servo pulse's width, s: 1.5 ms at the set-point 90 deg on the
// pulse's scale, k s more per degree (pwm_pulse_s_per_deg)
inline double rc_pulse_width_s(double k_s_per_deg, double sp_deg) { return 1.5e-3 + k_s_per_deg * (sp_deg - 90.0); }

// The largest pulse width per degree a file may give, s/deg: 100 us/deg
// (an 18 ms pulse over 180 degrees, near a 50 Hz frame; real servos take 5.6
// for 1-2 ms and 11.1 for 0.5-2.5 ms). A figure from the calibration's
// report, in us/deg, pasted as s/deg is caught by it.
constexpr double kMaxPulseSPerDeg = 1e-4;

// What is wrong with a combination of the effects' keys a file gave, naming
// the keys; empty when nothing is. Each key alone is checked by its reader.
inline const char* servo_params_conflict(const ServoParams& s) {
  if (s.pwm_pulse_s_per_deg > 0.0 && !(s.pwm_frame_s > 0.0))
    return "'pwm_pulse_s_per_deg' needs 'pwm_frame_s' (the pulses come once a frame)";
  if (s.deadband_deg > 0.0 && s.deadband_comparator_deg > 0.0)
    return "'deadband_deg' and 'deadband_comparator_deg' are two forms of one deadband: give one";
  return "";
}

}  // namespace chainsim
