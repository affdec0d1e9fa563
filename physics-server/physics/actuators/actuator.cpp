// Wire conversions by kind. See actuator.h.
#include "physics/actuators/actuator.h"

#include <stdexcept>

namespace chainsim {

Actuator make_actuator(int module, const ModuleDef& def, int a, dWorldID world,
                       const ModuleBodies& parts, const Eigen::Isometry3d& frame,
                       const ServoParams& servo, double h_s) {
  using Device = decltype(Actuator::device);
  const ActuatorDef& ad = def.actuators[a];
  switch (ad.type) {
    case ActuatorType::Servo: {
      const JointDef& jd = def.joints[ad.joint];
      return Actuator{module, true, -1,
                      Device(std::in_place_type<RotaryServo>, RotaryServo::params_of(ad, jd, servo), world,
                             parts.joints[ad.joint], parts.bodies[jd.child], parts.bodies[jd.parent],
                             Eigen::Vector3d(frame.linear() * jd.axis.normalized()))};
    }
    case ActuatorType::LinearServo: {
      const JointDef& jd = def.joints[ad.joint];
      return Actuator{module, true, -1,
                      Device(std::in_place_type<LinearServo>, LinearServo::params_of(ad, jd, servo, h_s), world,
                             parts.joints[ad.joint], parts.bodies[jd.child], parts.bodies[jd.parent],
                             Eigen::Vector3d(frame.linear() * jd.axis.normalized()))};
    }
    case ActuatorType::ScrewDrive: {
      ScrewDrive::Params p = ScrewDrive::params_of(ad, servo, h_s);
      p.direction = parts.offsets[ad.body].linear() * p.direction;  // the part's axis in its ODE body
      return Actuator{module, true, -1,
                      Device(std::in_place_type<ScrewDrive>, p, world, parts.bodies[ad.body])};
    }
    case ActuatorType::DcMotor: {
      const JointDef& jd = def.joints[ad.joint];
      return Actuator{module, true, -1,
                      Device(std::in_place_type<DcMotor>, DcMotor::params_of(ad, servo, h_s), world,
                             parts.joints[ad.joint], parts.bodies[jd.child], parts.bodies[jd.parent],
                             Eigen::Vector3d(frame.linear() * jd.axis.normalized()))};
    }
  }
  throw std::logic_error("unknown actuator type");
}

double setpoint_from_wire(ServoKind kind, int32_t wire) {
  switch (kind) {
    case ServoKind::Rotary: return RotaryServo::setpoint_from_wire(wire);
    case ServoKind::Linear: return LinearServo::setpoint_from_wire(wire);
    case ServoKind::Screw: return ScrewDrive::setpoint_from_wire(wire);
    case ServoKind::DcMotor: return DcMotor::setpoint_from_wire(wire);
  }
  return 0.0;
}

int32_t to_wire(ServoKind kind, double value) {
  switch (kind) {
    case ServoKind::Rotary: return RotaryServo::to_wire(value);
    case ServoKind::Linear: return LinearServo::to_wire(value);
    case ServoKind::Screw: return ScrewDrive::to_wire(value);
    case ServoKind::DcMotor: return DcMotor::to_wire(value);
  }
  return 0;
}

}  // namespace chainsim
