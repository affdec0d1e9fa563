// What the linear servo and the screw drive share (their force laws:
// model/module_def.h): how a step's force law is realised in ODE, and the
// motor current the force draws.
//
// Realised like the rotary servo (rotary_servo.h): the part of the force that
// depends on the end-of-step rate v' is a one-axis linear motor row (LMotor)
// with dParamVel = v*, dParamCFM = 1/D, dParamFMax = fmax, i.e.
// F = clamp(D (v* - v'), -fmax, fmax), solved implicitly by ODE with the
// whole system:
//  * the back-EMF term fmax v'/v_free: D = fmax / v_free;
//  * the linear servo's proportional term inside its band (|u| < 1) is taken
//    at the end-of-step position pos + h v' (backward Euler):
//    fmax (ref - pos - h v')/l0 adds D = fmax h / l0 (stable for any stiffness;
//    its numerical damping, fmax h / l0, is what keeps the pure paper law
//    with v_free = 0 from ringing forever).
// With no v'-dependent part at all (saturated, or a screw drive without
// v_free) the force is a plain external force. The linear motor is a separate
// joint (LMotor) rather than the slider's built-in motor, so that at a slider
// stop the law still holds (ODE replaces a powered joint's motor by its full
// fmax there).
#pragma once

#include <ode/ode.h>

#include <cstdint>

namespace chainsim {

// one step's force law: F = clamp(damping_n_s_m (target_rate_m_s - v'),
// -fmax, fmax) when damping_n_s_m > 0, else the constant force_n
struct ForceLaw {
  double damping_n_s_m = 0.0;
  double target_rate_m_s = 0.0;
  double force_n = 0.0;
};

// the law of a force known_force_n (known at the start of the step) plus a
// damping towards the rate that makes it so; no damping: a constant force
ForceLaw make_force_law(double known_force_n, double damping_n_s_m);

// sets the linear motor row for `law`; returns the plain force (N) the caller
// must still add along the axis this step (0 when the row carries the law)
double realise_force_law(const ForceLaw& law, dJointID lmotor, double fmax_n);

// the force the step applied, from the rate along the axis it ended with, N
double force_after_step(const ForceLaw& law, double rate_m_s, double fmax_n);

// The motor current of a force actuator (a linear driver: the supply delivers
// the motor current), |F| / fmax * stall current, and its RC-filtered
// magnitude as the current sensor sees it.
struct ForceMotorCurrent {
  double current_a = 0.0;           // signed, A
  double filtered_current_a = 0.0;  // RC-filtered |current|, A

  // after a step that applied force_n (driven: powered and enabled)
  void update(double force_n, double fmax_n, double stall_current_a, bool driven,
              double filter_decay);
  // 10-bit counts of the filtered current (0..1023); full scale <= 0: 0
  uint16_t adc_counts(double adc_full_scale_a) const;
};

// e^(-h/tau): the RC filter's decay over one step of h_s; tau <= 0: 0 (no filter)
double current_filter_decay(double tau_s, double h_s);

}  // namespace chainsim
