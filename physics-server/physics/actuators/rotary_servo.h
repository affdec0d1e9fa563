// A rotary servo on a hinge: the paper's DC servomotor model (servo_model.h)
// coupled to ODE. Each step the model gives its shaft torque as a linear
// damper, tau = D (v - w') with w' the end-of-step joint rate; a one-axis ODE
// angular motor on the hinge with dParamVel = v and dParamCFM = 1/D is exactly
// that damper (lambda = D (v - w_next)), solved with the whole multibody
// system, so the true effective inertia about the axis is used.
//
// Unit: radians, the hinge angle: 0 as assembled (straight), + = the child
// side turned positively about the joint axis (rotation module: pitch + lifts
// the module's rear, yaw + swings it to the right); range +-90 degrees on the
// shipped modules. The servo's own 0..180 degree scale is this angle + 90.
// Wire unit: millidegrees (set-point and measured angle alike).
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <cstdint>

#include "model/module_def.h"
#include "model/units.h"
#include "physics/actuators/servo_model.h"

namespace chainsim {

// The coupling of a servo model to ODE, shared by the World's rotary servos and
// the servo test stand (analysis/servo_bench): a one-axis angular motor whose
// force limit is far above any servo torque, driven each step by the model's
// step law as an implicit damper.
inline constexpr double kServoMotorFMax = 10.0;  // N m (the shipped servo stalls at 0.058 N m)
void drive_servo_motor(dJointID amotor, const ServoModel::StepLaw& law);

class RotaryServo {
 public:
  // configuration: fixed when the world is built
  struct Params {
    ServoParams motor;        // the paper's model (ActuatorDef::servo, else WorldConfig::servo)
    double lo_rad = -kPi;     // set-point range: the hinge's stops, else +-pi
    double hi_rad = kPi;
  };
  // what changes each step: the model's set-point, currents and effects
  struct State {
    ServoModel model;
  };
  // the ODE objects it reads and drives
  struct Ode {
    dJointID hinge = nullptr;  // body1 = child, body2 = parent
    dJointID motor = nullptr;  // one-axis angular motor on the same bodies, axis fixed in the child
  };

  // the configuration of actuator `ad` on hinge `joint`; servo: the world's
  // servo model, used when the actuator has none of its own
  static Params params_of(const ActuatorDef& ad, const JointDef& joint, const ServoParams& servo);
  // creates the angular motor on hinge (between child and parent, about axis_world)
  RotaryServo(const Params& params, dWorldID world, dJointID hinge, dBodyID child, dBodyID parent,
              const Eigen::Vector3d& axis_world);

  // the wire <-> radians conversion of every rotary servo
  static double setpoint_from_wire(int32_t millideg);
  static int32_t to_wire(double rad);

  const Params& params() const { return params_; }
  const ServoModel& model() const { return state_.model; }

  // the reference angle, rad, clamped to the range (NaN: ignored)
  void set_setpoint(double rad);
  double setpoint() const { return state_.model.setpoint(); }
  // a passive servo copies its master's set-point (the support module's arms)
  void copy_setpoint(const RotaryServo& master) { state_.model.set_setpoint(master.setpoint()); }

  double position() const;  // hinge angle now, rad (the potentiometer; also when limp)
  double rate() const;      // hinge rate now, rad/s
  int32_t position_wire() const { return to_wire(position()); }

  // start of a step of h_s seconds: the torque law, driven (powered and
  // enabled) or limp; end: the model advanced with the rate ODE produced
  void begin_step(bool driven, double h_s);
  void end_step();

  double current_a() const { return state_.model.current_a(); }
  double filtered_current_a() const { return state_.model.filtered_current_a(); }
  double effort() const { return state_.model.motor_torque_nm(); }  // N m, last step
  // drawn from the supply: a servo without drive free-wheels, its decaying
  // current is not drawn
  double supply_current_a() const;
  uint16_t adc_counts() const { return state_.model.adc_counts(); }

 private:
  const Params params_;
  State state_;
  Ode ode_;
};

}  // namespace chainsim
