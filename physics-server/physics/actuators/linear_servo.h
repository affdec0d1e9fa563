// The linear servo (paper eqs 4-5, the extension module) on a slider joint:
//   u = clamp((ref - pos)/l0, -1, 1),  F = clamp(fmax (u - v/v_free), -fmax, fmax)
// (model/module_def.h; realised in ODE as force_motor.h says).
//
// Unit: metres, the slider position: 0 as assembled, + = the child moved
// along the axis; the set-point is clamped to the slider's stops.
// Wire unit: micrometres (set-point and measured position alike).
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <cstdint>

#include "model/module_def.h"
#include "physics/actuators/force_motor.h"

namespace chainsim {

class LinearServo {
 public:
  // configuration: fixed when the world is built
  struct Params {
    double fmax_n = 0.0;           // stall force
    double l0_m = 0.0;             // proportional band
    double v_free_m_s = 0.0;       // no-load speed; 0 = no speed term (the paper's law)
    double stall_current_a = 0.0;  // motor current at |F| = fmax_n
    double lo_m = 0.0, hi_m = 0.0; // set-point range: the slider's stops (may be infinite)
    double adc_full_scale_a = 0.5; // current sense: 1023 counts
    double filter_decay = 0.0;     // the current filter's e^(-h/tau) per physics step
  };
  // what changes each step
  struct State {
    double setpoint_m = 0.0;       // reference position
    bool driven = false;           // powered and enabled during the last step
    ForceLaw law;                  // of the step under way
    double force_n = 0.0;          // applied over the last step
    ForceMotorCurrent current;     // motor current and its filtered magnitude
  };
  // the ODE objects it reads and drives
  struct Ode {
    dJointID slider = nullptr;     // body1 = child, body2 = parent
    dJointID motor = nullptr;      // one-axis linear motor, axis fixed in the parent
  };

  // the configuration of actuator `ad` on slider `joint`; servo: the world's
  // servo parameters (default stall current, current sense); h_s: the step
  static Params params_of(const ActuatorDef& ad, const JointDef& joint, const ServoParams& servo,
                          double h_s);
  // creates the linear motor (between child and parent, along axis_world)
  LinearServo(const Params& params, dWorldID world, dJointID slider, dBodyID child, dBodyID parent,
              const Eigen::Vector3d& axis_world);

  // the wire <-> metres conversion of every linear servo
  static double setpoint_from_wire(int32_t um);
  static int32_t to_wire(double m);

  const Params& params() const { return params_; }

  void set_setpoint(double m);  // clamped to the stroke (NaN: ignored)
  double setpoint() const { return state_.setpoint_m; }
  double position() const;      // slider position now, m (also when limp)
  double rate() const;          // slider rate now, m/s
  int32_t position_wire() const { return to_wire(position()); }

  // start of a step of h_s seconds (driven: powered and enabled); end: the
  // force and current of the step
  void begin_step(bool driven, double h_s);
  void end_step();

  double current_a() const { return state_.current.current_a; }
  double filtered_current_a() const { return state_.current.filtered_current_a; }
  double effort() const { return state_.force_n; }  // N, last step
  double supply_current_a() const;
  uint16_t adc_counts() const { return state_.current.adc_counts(params_.adc_full_scale_a); }

 private:
  const Params params_;
  State state_;
  Ode ode_;
};

}  // namespace chainsim
