// Module types as data (DESIGN.md section 5: "modules are data"). A ModuleDef
// says what a module is made of: rigid bodies (primitive shapes with the real
// masses), the joints between them, the actuators on those joints, its
// sensors, and its two docking faces. The World builds any ModuleDef
// generically; a later loader will read ModuleDefs from files, so everything a
// module type needs is here and nothing is type-specific C++.
//
// Frames and conventions
//  * Module frame: x = the chain's forward direction (towards the head), z up
//    when the chain lies on the ground as assembled, y = z cross x (left).
//    By convention the origin is the centre of the front docking face and the
//    module extends towards -x, but the World does not rely on that.
//  * Body frame: pose given in the module frame. Capsule and cylinder axes are
//    the body's local z (ODE's convention); box sides are along the body's
//    x, y, z. Bodies are solid and of uniform density: the World gives ODE the
//    mass and the shape, the inertia follows (body_inertia_kg_m2).
//  * Joints: anchor and axis in the module frame, as assembled. A hinge angle
//    (slider position) is the child's rotation (translation) relative to the
//    parent about (along) the axis, right-handed, 0 as assembled. Limits in
//    rad (hinge) or m (slider).
//  * Docking faces: a frame whose origin is the centre of the face and whose
//    x axis is the chain's forward direction. Docking module k+1 behind module k
//    makes k's back-face frame coincide with k+1's front-face frame, and fixes
//    k's back-face body to k+1's front-face body with a fixed joint.
//  * Units: SI (m, kg, rad, N, N m).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "servo_model.h"

namespace chainsim {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

enum class Shape { Capsule, Cylinder, Box, Sphere };

struct BodyDef {
  std::string name;            // unique in the module; used in traces (m<i>.<name>.x)
  Shape shape = Shape::Sphere;
  double radius_m = 0.0;       // capsule, cylinder, sphere
  // cylinder: full length; capsule: the straight part only (ODE's convention,
  // the overall length is length_m + 2 radius_m). Along the body's z.
  double length_m = 0.0;
  Eigen::Vector3d box_m = Eigen::Vector3d::Zero();  // box side lengths (x, y, z)
  double mass_kg = 0.0;
  Pose pose;                   // body frame in the module frame
};

enum class JointType { Hinge, Slider, Fixed };

struct JointDef {
  std::string name;
  JointType type = JointType::Hinge;
  int parent = -1;             // body index, the side towards the module's front
  int child = -1;              // body index
  Eigen::Vector3d anchor_m = Eigen::Vector3d::Zero();  // module frame (hinge)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();     // module frame (hinge, slider)
  double lo = -std::numeric_limits<double>::infinity();  // rad or m
  double hi = std::numeric_limits<double>::infinity();
};

enum class ActuatorType {
  Servo,        // DC servomotor on a hinge (servo_model.h); implemented
  LinearServo,  // paper eqs 4-5 on a slider: F = fmax * clamp((ref - pos)/l0, -1, 1)
  ScrewDrive,   // helicoidal module: a force along a body axis
};

struct ActuatorDef {
  std::string name;
  ActuatorType type = ActuatorType::Servo;
  int joint = -1;              // Servo, LinearServo: joint index
  int body = -1;               // ScrewDrive: body pushed
  // Servo: the motor model; empty = the World's WorldConfig::servo
  std::optional<ServoParams> servo;
  // Servo: >= 0 = a passive copy of that actuator's set-point (the support
  // module's two slave arms); not addressable by firmware. -1 = own set-point.
  int follows = -1;
  double fmax_n = 0.0;         // LinearServo max force; ScrewDrive force
  double l0_m = 0.0;           // LinearServo proportional band
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // ScrewDrive, body frame
};

enum class SensorType {
  // servo position is part of every Servo actuator (its potentiometer) and
  // needs no entry here
  MotorCurrent,    // filtered current of `actuator` -> 10-bit ADC `channel`
  Touch,           // any contact on `body` during the last step -> digital input bit `channel`
  Accelerometer,   // on `body`; not implemented by the World yet
  WheelEncoder,    // on `joint`, counter `channel`; not implemented by the World yet
};

struct SensorDef {
  std::string name;
  SensorType type = SensorType::MotorCurrent;
  int actuator = -1;
  int body = -1;
  int joint = -1;
  int channel = -1;            // ADC channel, digital input bit or counter index
};

struct DockingFace {
  int body = -1;               // the body the face belongs to
  Pose frame;                  // module frame; origin = face centre, x forward
};

struct ModuleDef {
  std::string type;            // "rotation", "passive", ...
  std::string description;
  std::vector<BodyDef> bodies;
  std::vector<JointDef> joints;
  std::vector<ActuatorDef> actuators;
  std::vector<SensorDef> sensors;
  DockingFace front;
  DockingFace back;
};

// the built-in types; throws std::invalid_argument naming the known types
ModuleDef builtin_module_def(const std::string& name);
std::vector<std::string> builtin_module_names();

// throws std::invalid_argument describing the first problem found (indices out
// of range, non-positive masses or sizes, duplicate names, zero axes, ...)
void validate_module_def(const ModuleDef& def);

// inertia tensor about the body's centre of mass in the body frame (solid,
// uniform density), kg m^2
Eigen::Matrix3d body_inertia_kg_m2(const BodyDef& body);
double module_mass_kg(const ModuleDef& def);
// the actuators firmware drives (type Servo, follows < 0), in definition
// order: servo s of a module is the s-th of these
std::vector<int> driven_servo_actuators(const ModuleDef& def);

const char* shape_name(Shape s);

}  // namespace chainsim
