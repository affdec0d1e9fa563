// The paper's DC servomotor model (section 3.2, Table 1); coupled to ODE by
// rotary_servo.h.
//
// Continuous model (output-shaft quantities; theta, w = joint angle and rate):
//   ea    = clamp(Kp (theta_r - theta), -Vs, Vs)      position loop + supply limit
//   L di/dt = ea - R i - Km w                          armature circuit
//   tau   = Kt i - B w - J dw/dt                       torque delivered to the joint
//   tau_f di_f/dt = |i| - i_f                          current sensor behind an RC filter
//   adc   = round(i_f / adc_full_scale_a * 1023)       10-bit ADC of the filtered current
//
// The electrical (L/R = 0.625 ms) and mechanical (J R/(Kt Km) = 0.43 ms)
// time constants are as short as the 0.5 ms physics step, so the model is not
// integrated with explicit Euler (that is unstable here). Per step h:
//  * the electrical part is integrated in closed form with ea held (sampled
//    from theta at the start of the step) and w held at its END-of-step value
//    w' (implicit). The step-average current is then affine in w':
//        i_avg = (1-phi) (ea - Km w')/R + phi i_n,  phi = (tau_e/h)(1 - e^(-h/tau_e))
//  * the rotor inertia J is a *relative* inertia (the geared rotor turns with
//    the joint's relative rate, not with the child body's absolute rate), so it
//    is not added to a body: it is integrated implicitly on the joint rate:
//    -J (w' - w_n)/h;
//  * B w is taken at w' (implicit).
// The total shaft torque over the step is therefore tau = D (v - w'), a linear
// damper towards a target rate v, with damping D. rotary_servo.h realises it as a
// one-axis ODE angular motor on the hinge with dParamVel = v and
// dParamCFM = 1/D (ODE's constraint-force mixing makes a motor row exactly an
// implicit damper: lambda = D (v - w_next)), so ODE solves it together with the
// whole multibody system: the *true* effective inertia about the axis (whatever
// the chain, the contacts and the joint limits do) is used, no estimate needed.
// After the step the current is advanced exactly with the w' ODE produced:
//   i_{n+1} = i_inf + (i_n - i_inf) e^(-h/tau_e),  i_inf = (ea - Km w')/R.
// Zero-inertia limit (a massless link): the scheme is still stable for h/tau_e
// = 0.8 (the current's step multiplier tends to -0.77); J > 0 keeps it further
// from that limit. See servo_model_test.cpp for the convergence check against a
// fine RK4 reference.
//
// Disabled / limp (no PWM pulses, or the module unpowered): the driver bridge is
// off, the motor terminals are open: no drive voltage and no closed circuit for
// the back-EMF, so there is no electrical braking; the current still flowing
// decays with L/R (free-wheel) and then there is no torque at all. B and J stay
// (they are mechanical).
//
// Static friction (the paper's I_threshold, "a range [0..Ithreshold] where
// intensity does not produce any torque"): ServoParams::i_threshold_a, default
// 0 = off. When > 0 the electromagnetic torque is Kt dz(i), with the dead zone
//   dz(i) = 0 for |i| <= I_th,  i - I_th sign(i) beyond
// (continuous, like a Simulink Dead Zone block before Kt, so no chatter at
// the edge). The current itself is not affected (it still flows and is
// measured). Each step the branch is chosen from the step-average current
// predicted with w' = w (the rate at the start of the step); within the branch
// the torque stays affine in w' and implicit as above. Consequences: a servo
// holding a load has a steady error of up to I_th R / Kp (0.05 A: 2.9 degrees
// with Table 1), and in the dead band the electrical braking is gone.
//
// Effect catalogue (docs/calibration.md; `chainsim calibrate` names them). Each
// is off by default and its parameter's null value (0) removes it exactly:
//  * static_friction_threshold  i_threshold_a (above).
//  * coulomb_friction  coulomb_nm: output-side friction torque -Tc tanh(w/ws),
//    ws = kCoulombRate (0.005 rad/s; tanh by fast_tanh.h), linearised at the start-of-step rate with
//    the slope implicit (a damper Tc sech^2/ws added to the law), so a holding
//    joint sticks without chatter.
//  * backlash  backlash_deg: gear play of that total width between the motor
//    side and the output (the potentiometer is on the output). Engaged on the
//    side the motor torque pushes, the law is the full one; while the motor
//    crosses the gap the joint gets no motor torque and the rotor (J, B, the
//    electrical circuit, back-EMF at the rotor rate) is integrated here,
//    implicitly; the gap closes inelastically (a plastic impact: the step
//    after closing takes the rotor's momentum J wm at its own rate into the
//    joint's, and the gap cannot reopen within that step). Compliant variant,
//    backlash_stiffness_nm_rad > 0: the mesh is a spring of that stiffness
//    with a damper c = 2 sqrt(k J) (critical for the rotor against a held
//    output) acting on the penetration beyond the half play; the rotor always
//    has its own state (a two-inertia gear), the joint gets the contact
//    torque, both implicit in the step (see begin_step).
//  * deadband  deadband_deg: the servo amplifier ignores position errors within
//    +-deadband/2 (continuous dead zone on the error before Kp).
//    Comparator form, deadband_comparator_deg: no drive within +-width/2,
//    the whole error outside (an analogue servo's window comparator gates
//    the amplifier; the drive jumps at the window's edge).
//  * supply_sag  supply_sag_ohm: internal resistance of the supply; the bridge's
//    duty cycle is applied to Vs - Rs |i| (i at the start of the step): a PWM
//    bridge. Linear-driver variant, supply_sag_linear_ohm: the drive keeps its
//    small-signal gain Kp and only its limit drops, |ea| <= Vs - Rs |i|.
//    Rail variant of either form, supply_rail_f = C > 0: the driver draws
//    from a rail capacitor C that the supply charges through Rs,
//      C dV/dt = (Vs - V)/Rs - i_s,
//    i_s = duty x i for the PWM bridge (signed: braking returns current to the
//    rail), |i| for the linear driver; the bridge applies duty x V, the linear
//    driver's limit is V. V is held over a step (its start value) and then
//    advanced exactly with the step-average draw. C = 0: the forms above.
//  * pwm_frame_delay  pwm_frame_s: the set-point reaches the servo only at its
//    pulse frames, every pwm_frame_s seconds (0.02 s: 50 Hz), the first at
//    pwm_frame_phase_s after reset_state (before it the servo keeps the
//    set-point it had). A frame inside a step acts for the part of the step
//    after it (the step's drive uses the time-weighted mean set-point).
//    Falling-edge variant, pwm_pulse_s_per_deg = k > 0: a frame starts a
//    pulse whose width carries the set-point of that moment, 1.5 ms + k (sp +
//    pwm_pulse_origin_deg - 90 deg) (the RC convention: 1.5 ms is the middle;
//    the origin 90, the default, puts it at a module's joint angle 0), and
//    the servo's decoder acts on it at the pulse's falling edge, so the delay
//    depends on the set-point as well as on the frame phase.
//  * current_limit  current_limit_a: the driver limits the drive voltage to
//    Km w +- R I_lim (w at the start of the step), so |i| settles at <= I_lim.
#pragma once

#include <cstdint>

#include "model/servo_params.h"

namespace chainsim {

// the smoothing rate of coulomb_friction, rad/s
constexpr double kCoulombRate = 0.005;

class ServoModel {
 public:
  // the torque law for one physics step: tau = damping * (target_rate - w_next)
  struct StepLaw {
    double target_rate = 0.0;   // rad/s
    double damping = 0.0;       // N m s/rad, > 0 (1/damping = the motor row's CFM)
    // damping * target_rate as summed, before the division (N m): a solver
    // that needs the torque rather than the rate (the bench's closed form)
    // uses it and saves a division and its rounding
    double torque0 = 0.0;
    // the law of a torque0 and a damping (the rate derived from them)
    static StepLaw of(double torque0, double damping) { return {torque0 / damping, damping, torque0}; }
  };

  explicit ServoModel(const ServoParams& params = ServoParams{});

  const ServoParams& params() const { return p_; }

  void set_setpoint(double rad) { setpoint_ = rad; }
  double setpoint() const { return setpoint_; }
  // disabled = no drive (limp); see above
  void set_enabled(bool enabled) { enabled_ = enabled; }
  bool enabled() const { return enabled_; }

  // Start of a step of length h (s): theta, w = joint angle and rate now.
  StepLaw begin_step(double theta, double w, double h);
  // End of the step: w_next = the joint rate the physics produced.
  void end_step(double w_next);

  // the set-point the servo acts on (differs from setpoint() under pwm_frame_delay)
  double applied_setpoint() const { return applied_; }
  // backlash: motor-side angle minus output angle, rad (0 without backlash)
  double backlash_offset() const { return delta_; }

  double current_a() const { return i_; }              // armature current now
  double mean_current_a() const { return i_mean_; }    // average over the last step
  double filtered_current_a() const { return i_f_; }   // after the RC filter
  double drive_voltage_v() const { return ea_; }       // ea of the last step
  // Kt dz(i): electromagnetic torque, last step average (dz = the static-friction dead zone)
  double motor_torque_nm() const { return p_.kt * dead_zone(i_mean_); }
  // 10-bit counts of the filtered current (0..1023)
  uint16_t adc_counts() const;

  // back to rest: no current, filter empty (set-point and enable kept)
  void reset_state();

 private:
  void update_constants(double h);
  double dead_zone(double i) const;

  double drive_voltage(double setpoint, double theta, double wr) const;

  ServoParams p_;
  double setpoint_ = 0.0;
  bool enabled_ = true;

  // state
  double i_ = 0.0;
  double i_f_ = 0.0;
  double i_mean_ = 0.0;
  double time_s_ = 0.0;      // since reset_state (pwm frames)
  long long frame_ = -1;     // the last pwm frame latched
  double applied_ = 0.0;     // set-point latched at the last frame
  // pwm_frame_delay, falling edge: the set-point the pulse under way carries
  // and the time it acts (its falling edge; < 0: none under way)
  double pending_ = 0.0;
  double latch_s_ = -1.0;
  double rail_v_ = 0.0;      // supply_sag, rail variant: the rail voltage, V
  double delta_ = 0.0;       // backlash: motor side - output, rad
  double wm_ = 0.0;          // backlash: motor-side rate, rad/s
  bool engaged_ = true;      // backlash: gap closed
  bool gap_step_ = false;    // backlash: this step the rotor crossed the gap alone
  bool closed_ = false;      // backlash: the gap closed in the last step (rotor rate wm_)
  // compliant backlash, this step: rotor rate wm' = (mesh_m_ - mesh_kp_ + mesh_k2_ w') / mesh_a_
  // (in contact; mesh_kp_ = mesh_k2_ = 0 out of it)
  bool mesh_step_ = false;
  double mesh_a_ = 1.0, mesh_m_ = 0.0, mesh_kp_ = 0.0, mesh_k2_ = 0.0;
  // held over the current step
  double ea_ = 0.0;
  bool drive_ = true;   // enabled_ at begin_step
  // constants for h
  double h_ = -1.0;
  double e_ = 0.0;      // e^(-h/tau_e)
  double phi_ = 0.0;    // (tau_e/h)(1 - e^(-h/tau_e)): weight of i_n in the step average
  double ef_ = 0.0;     // e^(-h/tau_f)
  double jh_ = 0.0;     // J/h
  // 1/R and (1 - phi)/R: multiplications in the step where it divided by R
  // (a division's latency twice on the step's chain of dependent operations)
  double inv_r_ = 0.0;
  double drive_gain_ = 0.0;
  double ci_ = 0.0;     // Km (1 - phi)/R: the step-average current's slope in w' when driven
  double rail_rs_ = 0.0;  // supply_sag's Rs when the rail variant is on, else 0
  double er_ = 0.0;       // e^(-h/(Rs C))
};

}  // namespace chainsim

// the step, defined inline
#include "physics/actuators/servo_model_step.h"
