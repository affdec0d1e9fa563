// A firmware-driven actuator of any kind, as the World holds them: a rotary
// servo, a linear servo, a screw drive or a DC motor (one file each, each
// with its Params, State and ODE objects), the module it belongs to and
// whether firmware enables it. Values "in the actuator's unit" are radians
// (rotary), metres (linear) or the -1..1 drive command (screw drive, DC
// motor); on the wire each kind has its own integer unit (millidegrees,
// micrometres, per mille), converted in that kind's file only.
#pragma once

#include <cstdint>
#include <variant>

#include "physics/actuators/dc_motor.h"
#include "physics/actuators/linear_servo.h"
#include "physics/actuators/rotary_servo.h"
#include "physics/actuators/screw_drive.h"
#include "physics/module_builder.h"

namespace chainsim {

// the index of each kind in Actuator::device
enum class ServoKind { Rotary, Linear, Screw, DcMotor };

struct Actuator {
  int module = -1;
  bool enabled = true;  // a disabled actuator gets no drive (no pulses): it is limp
  // rotary servos only: >= 0 = the World's index of the servo whose set-point
  // and enable this one copies (the support module's passive arms)
  int follows = -1;
  std::variant<RotaryServo, LinearServo, ScrewDrive, DcMotor> device;

  ServoKind kind() const { return static_cast<ServoKind>(device.index()); }

  // the generic interface every kind has, in the actuator's unit
  template <class F>
  decltype(auto) visit(F&& f) { return std::visit(std::forward<F>(f), device); }
  template <class F>
  decltype(auto) visit(F&& f) const { return std::visit(std::forward<F>(f), device); }
};

// actuator a of module `module` (index in the World), on the module's parts
// built in `frame`; servo: the world's servo parameters; h_s: the physics step
Actuator make_actuator(int module, const ModuleDef& def, int a, dWorldID world,
                       const ModuleBodies& parts, const Eigen::Isometry3d& frame,
                       const ServoParams& servo, double h_s);

// a wire value (protocol servo_setpoint) in the actuator's unit
double setpoint_from_wire(ServoKind kind, int32_t wire);
// a value in the actuator's unit as a wire value (protocol servo_pos)
int32_t to_wire(ServoKind kind, double value);

}  // namespace chainsim
