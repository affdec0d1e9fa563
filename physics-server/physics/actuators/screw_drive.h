// The screw drive (the helicoidal module): a force along a body axis, against
// the static environment,
//   F = clamp(fmax (u - v/v_free), -fmax, fmax)
// u = the drive command, v = the body's velocity along the axis
// (model/module_def.h; realised in ODE as force_motor.h says).
//
// Unit: the signed drive command u, -1..1 (a fraction of the supply voltage,
// like a PWM duty cycle), clamped. It has no position sensor: its "measured
// position" echoes the command. Wire unit: the servo pulse its speed
// controller takes, in millidegrees as a servo's: -90000..90000 (1.0 .. 2.0
// ms) = full reverse .. full forward (setspangle's -9000..9000 cdeg).
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <cstdint>

#include "model/module_def.h"
#include "physics/actuators/force_motor.h"

namespace chainsim {

class ScrewDrive {
 public:
  // configuration: fixed when the world is built
  struct Params {
    double fmax_n = 0.0;           // stall force
    double v_free_m_s = 0.0;       // no-load speed at full drive; 0 = no speed term
    double stall_current_a = 0.0;  // motor current at |F| = fmax_n
    Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // drive axis, body frame, unit
    double adc_full_scale_a = 0.5; // current sense: 1023 counts
    double filter_decay = 0.0;     // the current filter's e^(-h/tau) per physics step
  };
  // what changes each step
  struct State {
    double command = 0.0;          // u, -1..1
    bool driven = false;           // powered and enabled during the last step
    ForceLaw law;                  // of the step under way
    double force_n = 0.0;          // applied over the last step
    ForceMotorCurrent current;     // motor current and its filtered magnitude
  };
  // the ODE objects it reads and drives
  struct Ode {
    dBodyID body = nullptr;        // the body pushed
    dJointID motor = nullptr;      // one-axis linear motor on the body alone, axis fixed in it
  };

  // the configuration of actuator `ad`; servo: the world's servo parameters
  // (default stall current, current sense); h_s: the physics step
  static Params params_of(const ActuatorDef& ad, const ServoParams& servo, double h_s);
  // creates the linear motor on body
  ScrewDrive(const Params& params, dWorldID world, dBodyID body);

  // the wire <-> command conversion of every screw drive
  static double setpoint_from_wire(int32_t millideg);
  static int32_t to_wire(double command);

  const Params& params() const { return params_; }

  void set_setpoint(double command);  // clamped to -1..1 (NaN: ignored)
  double setpoint() const { return state_.command; }
  double position() const { return state_.command; }  // no sensor: echoes the command
  double rate() const;  // the body's velocity along the drive axis now, m/s
  int32_t position_wire() const { return to_wire(position()); }

  // start of a step (driven: powered and enabled); end: the force and
  // current of the step
  void begin_step(bool driven, double h_s);
  void end_step();

  double current_a() const { return state_.current.current_a; }
  double filtered_current_a() const { return state_.current.filtered_current_a; }
  double effort() const { return state_.force_n; }  // N, last step
  double supply_current_a() const;
  uint16_t adc_counts() const { return state_.current.adc_counts(params_.adc_full_scale_a); }

 private:
  Eigen::Vector3d axis_world() const;

  const Params params_;
  State state_;
  Ode ode_;
};

}  // namespace chainsim
