// Module types as data: a module type is a definition file, not C++. A ModuleDef
// says what a module is made of: rigid bodies (primitive shapes with the real
// masses), the joints between them, the actuators on those joints, its
// sensors, and its two docking faces. The World builds any ModuleDef
// generically; module_file.h reads ModuleDefs from YAML files (the format:
// docs/module-format.md; the built-in types are scenes/modules/*.yaml), so
// everything a module type needs is here and nothing is type-specific C++.
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
//    makes k's back-face frame coincide with k+1's front-face frame, and joins
//    k's back-face body to k+1's front-face body rigidly (one ODE body,
//    physics/module_builder.h).
//  * Units: SI (m, kg, rad, N, N m).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "model/wheel_def.h"
#include "model/servo_params.h"

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
  // false: no collision geom (a part inside another body, like the helicoidal
  // module's spinning head, whose wheels touch the wall for it)
  bool collides = true;
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
  // Hinge: viscous friction, torque = -friction * relative rate, N m s/rad
  // (the traveller's wheels, paper 3.3.6); 0 = none. Realised in sensors.cpp.
  double friction_nm_s_rad = 0.0;
};

// All three are driven by firmware through the World's servo index API
// (each kind's file in physics/actuators/ says what its set-point means).
// Their force laws:
//  * Servo: the paper's DC servomotor model, servo_model.h.
//  * LinearServo (paper eqs 4-5, extension module), on a slider joint:
//      u = clamp((ref - pos)/l0_m, -1, 1)          drive fraction
//      F = clamp(fmax_n (u - v/v_free_m_s), -fmax_n, fmax_n)
//    v = the slider rate; v_free_m_s = 0 drops the speed term (F = fmax u,
//    the paper's law exactly). The speed term is the motor's back-EMF (its
//    force-speed line: fmax at stall, 0 at v_free): without it the law is an
//    undamped spring.
//  * ScrewDrive (helicoidal module): a force along `direction` (body frame)
//    on `body`, relative to the static environment:
//      F = clamp(fmax_n (u - v/v_free_m_s), -fmax_n, fmax_n)
//    u = the drive command -1..1 (the set-point), v = the body's velocity
//    along the direction; v_free_m_s = 0: F = fmax u (no speed drop).
//  * DcMotor (a gear motor on a hinge, e.g. the helicoidal module's spinning
//    head): a torque about the hinge axis between its two bodies,
//      tau = clamp(fmax_n (u - w/v_free_m_s), -fmax_n, fmax_n)
//    with fmax_n = the stall torque (N m), v_free_m_s = the no-load speed
//    (rad/s, > 0), w = the hinge rate, u = the drive command -1..1. The
//    reaction acts on the other body (physics/actuators/dc_motor.h).
// Supply current of both (the rotary servo's rule: a linear driver, the
// supply delivers the motor current): |F| / fmax_n * stall_current_a.
enum class ActuatorType {
  Servo,        // DC servomotor on a hinge (servo_model.h)
  LinearServo,  // paper eqs 4-5 on a slider (above)
  ScrewDrive,   // a force along a body axis (above)
  DcMotor,      // a torque on a hinge (above); driven like a screw drive
};

struct ActuatorDef {
  std::string name;
  ActuatorType type = ActuatorType::Servo;
  int joint = -1;              // Servo, LinearServo, DcMotor: joint index
  int body = -1;               // ScrewDrive: body pushed
  // Servo: the motor model; empty = the World's WorldConfig::servo
  std::optional<ServoParams> servo;
  // Servo: >= 0 = a passive copy of that actuator's set-point (the support
  // module's two slave arms); not addressable by firmware. -1 = own set-point.
  int follows = -1;
  double fmax_n = 0.0;         // LinearServo, ScrewDrive: max (stall) force, N, > 0; DcMotor: N m
  double l0_m = 0.0;           // LinearServo: proportional band, m, > 0
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // ScrewDrive, body frame
  // LinearServo, ScrewDrive: no-load speed at full drive, m/s; 0 = no speed
  // term. DcMotor: rad/s, > 0
  double v_free_m_s = 0.0;
  // LinearServo, ScrewDrive: motor current at |F| = fmax_n, A; 0 = the World's
  // servo stall current (WorldConfig::servo: supply_v / r = 0.42 A)
  double stall_current_a = 0.0;
};

enum class SensorType {
  // servo position is part of every Servo actuator (its potentiometer) and
  // needs no entry here
  MotorCurrent,    // filtered current of `actuator` (any type) -> 10-bit ADC `channel`
  Touch,           // any contact on `body` during the last step -> digital input bit `channel`
  // 3-axis, on `body`, ADC channels channel, +1, +2 = its x, y, z (sensors.h)
  Accelerometer,
  WheelEncoder,    // on hinge `joint`: counter `channel` counts its rotation (sensors.h)
};

struct SensorDef {
  std::string name;
  SensorType type = SensorType::MotorCurrent;
  int actuator = -1;
  int body = -1;
  int joint = -1;
  int channel = -1;            // ADC channel (accelerometer: the first of 3), digital input bit or counter index
  // Accelerometer: counts = 512 + a / g0 * 512 / range_g, clamped to 0..1023
  // (a = specific force along the axis, g0 = 9.80665 m/s^2)
  double range_g = 3.0;
  double noise_g = 0.0;        // Gaussian noise, standard deviation (deterministic, from the world seed)
  double bandwidth_hz = 0.0;   // first-order low-pass filter; 0 = none
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // sensor axes in the module frame
  // WheelEncoder: counts per revolution of the joint
  int counts_per_rev = 360;
  // Touch: sectors > 1 makes the body's surface that many switches around
  // the module's x axis, switch k at first_deg + k 360 / sectors (0 = up,
  // the module's +z; 90 = left, +y) on digital input bit channel + k. A
  // contact fires the switches within half_width_deg of its direction
  // around the axis, and all of them when it pushes along the axis (its
  // normal within 37 degrees of x). sectors = 1: any contact, one input.
  int sectors = 1;
  double first_deg = 0;
  double half_width_deg = 180;   // the module file's default is 180 / sectors
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
  std::vector<WheelSetDef> wheels;   // spring-loaded wheels on the wall (wheel_def.h)
  std::vector<PadDef> pads;          // friction pads (wheel_def.h)
  DockingFace front;
  DockingFace back;
};

// the built-in types: scenes/modules/<name>.yaml, compiled in (module_file.h);
// throws std::invalid_argument naming the known types
ModuleDef builtin_module_def(const std::string& name);
std::vector<std::string> builtin_module_names();
// `name` from `types` (e.g. WorldConfig::module_types, a scene's own types)
// if there, else the built-in
ModuleDef find_module_def(const std::vector<ModuleDef>& types, const std::string& name);

// throws std::invalid_argument describing the first problem found (indices out
// of range, non-positive masses or sizes, duplicate names, zero axes, ...)
void validate_module_def(const ModuleDef& def);

// inertia tensor about the body's centre of mass in the body frame (solid,
// uniform density), kg m^2
Eigen::Matrix3d body_inertia_kg_m2(const BodyDef& body);
double module_mass_kg(const ModuleDef& def);
// the actuators firmware drives (any type, follows < 0), in definition
// order: servo s of a module is the s-th of these
std::vector<int> driven_servo_actuators(const ModuleDef& def);

const char* shape_name(Shape s);

}  // namespace chainsim
