// A DC gear motor on a hinge (the helicoidal module's spun head): a torque
// about the hinge axis between its two bodies,
//   tau = clamp(tau_stall (u - w/w_free), -tau_stall, tau_stall)
// u = the drive command, w = the hinge rate (model/module_def.h). Realised
// like the force actuators (force_motor.h) on a one-axis angular motor
// between the hinge's bodies: the back-EMF part is the row's damping
// D = tau_stall / w_free, solved implicitly with the whole system; the
// reaction acts on the hinge's other body.
//
// Unit: the signed drive command u, -1..1, clamped (as the screw drive). It
// has no position sensor: its "measured position" echoes the command. Wire
// unit: the screw drive's, a servo pulse in millidegrees, -90000..90000 =
// full reverse .. full forward.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <cstdint>

#include "model/module_def.h"
#include "physics/actuators/force_motor.h"

namespace chainsim {

class DcMotor {
 public:
  // configuration: fixed when the world is built
  struct Params {
    double stall_torque_nm = 0.0;
    double free_speed_rad_s = 0.0;  // no-load speed at full drive, > 0
    double stall_current_a = 0.0;   // motor current at |tau| = stall torque
    double adc_full_scale_a = 0.5;  // current sense: 1023 counts
    double filter_decay = 0.0;      // the current filter's e^(-h/tau) per physics step
  };
  // what changes each step
  struct State {
    double command = 0.0;           // u, -1..1
    bool driven = false;            // powered and enabled during the last step
    ForceLaw law;                   // of the step under way (N m, rad/s)
    double torque_nm = 0.0;         // applied over the last step
    ForceMotorCurrent current;
  };
  // the ODE objects it reads and drives
  struct Ode {
    dJointID hinge = nullptr;       // body1 = child, body2 = parent
    dJointID motor = nullptr;       // one-axis angular motor on the same bodies
  };

  static Params params_of(const ActuatorDef& ad, const ServoParams& servo, double h_s);
  // creates the angular motor on hinge (between child and parent, about axis_world)
  DcMotor(const Params& params, dWorldID world, dJointID hinge, dBodyID child, dBodyID parent,
          const Eigen::Vector3d& axis_world);

  // the wire <-> command conversion of every DC motor (the screw drive's)
  static double setpoint_from_wire(int32_t millideg);
  static int32_t to_wire(double command);

  const Params& params() const { return params_; }

  void set_setpoint(double command);  // clamped to -1..1 (NaN: ignored)
  double setpoint() const { return state_.command; }
  double position() const { return state_.command; }  // no sensor: echoes the command
  double rate() const;  // hinge rate now, rad/s
  int32_t position_wire() const { return to_wire(position()); }

  void begin_step(bool driven, double h_s);
  void end_step();

  double current_a() const { return state_.current.current_a; }
  double filtered_current_a() const { return state_.current.filtered_current_a; }
  double effort() const { return state_.torque_nm; }  // N m, last step
  double supply_current_a() const;
  uint16_t adc_counts() const { return state_.current.adc_counts(params_.adc_full_scale_a); }

 private:
  const Params params_;
  State state_;
  Ode ode_;
};

}  // namespace chainsim
