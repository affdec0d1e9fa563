// The rotary servo's coupling to ODE. See rotary_servo.h.
#include "physics/actuators/rotary_servo.h"

#include <algorithm>
#include <cmath>

#include "physics/actuators/wire_value.h"

namespace chainsim {
void drive_servo_motor(dJointID amotor, const ServoModel::StepLaw& law) {
  dJointSetAMotorParam(amotor, dParamVel, law.target_rate);
  dJointSetAMotorParam(amotor, dParamCFM, 1.0 / law.damping);
}

RotaryServo::Params RotaryServo::params_of(const ActuatorDef& ad, const JointDef& joint,
                                           const ServoParams& servo) {
  Params p;
  p.motor = ad.servo.value_or(servo);
  p.lo_rad = std::isfinite(joint.lo) ? joint.lo : -kPi;
  p.hi_rad = std::isfinite(joint.hi) ? joint.hi : kPi;
  return p;
}

RotaryServo::RotaryServo(const Params& params, dWorldID world, dJointID hinge, dBodyID child,
                         dBodyID parent, const Eigen::Vector3d& axis_world)
    : params_(params), state_{ServoModel(params.motor)} {
  ode_.hinge = hinge;
  ode_.motor = dJointCreateAMotor(world, nullptr);
  dJointAttach(ode_.motor, child, parent);
  dJointSetAMotorMode(ode_.motor, dAMotorUser);
  dJointSetAMotorNumAxes(ode_.motor, 1);
  dJointSetAMotorAxis(ode_.motor, 0, 1, axis_world.x(), axis_world.y(), axis_world.z());
  dJointSetAMotorParam(ode_.motor, dParamFMax, kServoMotorFMax);
}

double RotaryServo::setpoint_from_wire(int32_t millideg) { return deg_to_rad(millideg * 1e-3); }

int32_t RotaryServo::to_wire(double rad) { return round_to_wire(rad_to_deg(rad) * 1e3); }

void RotaryServo::set_setpoint(double rad) {
  if (std::isnan(rad)) return;
  state_.model.set_setpoint(std::clamp(rad, params_.lo_rad, params_.hi_rad));
}

double RotaryServo::position() const { return dJointGetHingeAngle(ode_.hinge); }

double RotaryServo::rate() const { return dJointGetHingeAngleRate(ode_.hinge); }

void RotaryServo::begin_step(bool driven, double h_s) {
  ServoModel& m = state_.model;
  m.set_enabled(driven);
  drive_servo_motor(ode_.motor, m.begin_step(position(), rate(), h_s));
}

void RotaryServo::end_step() { state_.model.end_step(rate()); }

double RotaryServo::supply_current_a() const {
  return state_.model.enabled() ? std::fabs(state_.model.current_a()) : 0.0;
}

}  // namespace chainsim
