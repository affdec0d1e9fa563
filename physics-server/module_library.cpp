// Built-in module types and ModuleDef helpers. See module_library.h.
#include "module_library.h"

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

namespace chainsim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// rotation taking the body's z axis (ODE's capsule/cylinder axis) onto the
// module's x axis: +90 degrees about y
Eigen::Quaterniond z_along_x() {
  return Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitY()));
}

BodyDef make_body(std::string name, Shape shape, double radius, double length, double mass,
                  double x_centre) {
  BodyDef b;
  b.name = std::move(name);
  b.shape = shape;
  b.radius_m = radius;
  b.length_m = length;
  b.mass_kg = mass;
  b.pose.position = Eigen::Vector3d(x_centre, 0.0, 0.0);
  b.pose.orientation = z_along_x();
  return b;
}

// Rotation module (paper 3.3.1, Fig. 5a): a capsule and two cylinders as
// connectors, two servos: pitch (front) then yaw (back), each limited to +-90
// degrees (the real servos have 180 degrees of travel).
//
//   x = 0      -5                -16.5        -29.5          -41   -46 mm
//   | front  |( capsule: servo pitch o ...... o servo yaw  )| back  |
//   front face                                                 back face
//
// Sizes and masses (the MICROTUB modules are about 25 mm in diameter and about
// 10 g each; the paper gives no per-part figures, these are our estimates):
//  * overall length 46 mm: two micro servos (about 23 x 12 x 20 mm each, the
//    smallest hobby class) placed crosswise, plus the docking rings.
//  * connectors: cylinders of radius 12.5 mm (the module's 25 mm diameter; the
//    docking rings are its widest part), 5 mm thick (a ring with the docking
//    pins and the bus/sync connector), 1.5 g each (a 25 mm disc of PCB and
//    plastic; a solid ABS disc would be 2.6 g, the ring is mostly hollow).
//  * capsule: radius 11.5 mm (the shell sits just inside the rings, so a
//    straight module rests on its rings), overall length 36 mm (straight part
//    13 mm), 7 g: two micro servos of about 2.5 g each plus the PCB with the
//    microcontroller and the shell (about 2 g). Total 10 g.
//  * servo axes at the centres of the capsule's end caps (x = -16.5 and -29.5
//    mm): the capsule turns about its cap centres, so it never sweeps into its
//    own rings, as with the real servo horns.
ModuleDef rotation_def() {
  ModuleDef d;
  d.type = "rotation";
  d.description =
      "rotation module (paper 3.3.1): capsule + two cylinder connectors, pitch then yaw servo, "
      "+-90 deg, 25 mm diameter, 46 mm long, 10 g";
  const double ring_r = 0.0125, ring_len = 0.005, ring_m = 0.0015;
  const double cap_r = 0.0115, cap_straight = 0.013, cap_m = 0.007;
  const double cap_front = -ring_len;                                     // -5 mm
  const double cap_back = cap_front - (cap_straight + 2.0 * cap_r);       // -41 mm
  const double back_face = cap_back - ring_len;                           // -46 mm
  const double pitch_x = cap_front - cap_r;                               // -16.5 mm
  const double yaw_x = cap_back + cap_r;                                  // -29.5 mm

  d.bodies.push_back(make_body("front", Shape::Cylinder, ring_r, ring_len, ring_m, -ring_len / 2));
  d.bodies.push_back(make_body("body", Shape::Capsule, cap_r, cap_straight, cap_m,
                               (cap_front + cap_back) / 2));
  d.bodies.push_back(
      make_body("back", Shape::Cylinder, ring_r, ring_len, ring_m, back_face + ring_len / 2));

  JointDef pitch;
  pitch.name = "pitch";
  pitch.type = JointType::Hinge;
  pitch.parent = 0;
  pitch.child = 1;
  pitch.anchor_m = Eigen::Vector3d(pitch_x, 0, 0);
  pitch.axis = Eigen::Vector3d::UnitY();   // bends in the vertical plane
  pitch.lo = -kPi / 2;
  pitch.hi = kPi / 2;
  d.joints.push_back(pitch);

  JointDef yaw = pitch;
  yaw.name = "yaw";
  yaw.parent = 1;
  yaw.child = 2;
  yaw.anchor_m = Eigen::Vector3d(yaw_x, 0, 0);
  yaw.axis = Eigen::Vector3d::UnitZ();     // bends in the ground plane
  d.joints.push_back(yaw);
  // signs (hinge angle = child relative to parent about the axis): pitch > 0
  // lifts the rear of the module, yaw > 0 swings its rear to the right (-y)

  ActuatorDef s0;
  s0.name = "pitch_servo";
  s0.type = ActuatorType::Servo;
  s0.joint = 0;
  d.actuators.push_back(s0);
  ActuatorDef s1 = s0;
  s1.name = "yaw_servo";
  s1.joint = 1;
  d.actuators.push_back(s1);

  SensorDef c0;
  c0.name = "pitch_current";
  c0.type = SensorType::MotorCurrent;
  c0.actuator = 0;
  c0.channel = 0;
  d.sensors.push_back(c0);
  SensorDef c1 = c0;
  c1.name = "yaw_current";
  c1.actuator = 1;
  c1.channel = 1;
  d.sensors.push_back(c1);

  d.front.body = 0;
  d.front.frame.position = Eigen::Vector3d::Zero();
  d.back.body = 2;
  d.back.frame.position = Eigen::Vector3d(back_face, 0, 0);
  return d;
}

// Passive module: one rigid body the size of a rotation module: a capsule of
// radius 12 mm (about the 25 mm diameter) and 46 mm overall (the rotation
// module's length, so chains keep their spacing), 10 g (the same class of
// module: shell, PCB, connectors, no servos but ballast-free). Both docking
// faces are on the capsule's tips.
ModuleDef passive_def() {
  ModuleDef d;
  d.type = "passive";
  d.description = "passive module: one capsule, 24 mm diameter, 46 mm long, 10 g";
  const double r = 0.012, overall = 0.046, mass = 0.010;
  d.bodies.push_back(make_body("body", Shape::Capsule, r, overall - 2 * r, mass, -overall / 2));
  d.front.body = 0;
  d.back.body = 0;
  d.back.frame.position = Eigen::Vector3d(-overall, 0, 0);
  return d;
}

struct Builtin {
  const char* name;
  ModuleDef (*make)();
};
const Builtin kBuiltins[] = {
    {"rotation", rotation_def},
    {"passive", passive_def},
};

[[noreturn]] void invalid(const ModuleDef& d, const std::string& what) {
  throw std::invalid_argument("module type '" + d.type + "': " + what);
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

const char* shape_name(Shape s) {
  switch (s) {
    case Shape::Capsule: return "capsule";
    case Shape::Cylinder: return "cylinder";
    case Shape::Box: return "box";
    case Shape::Sphere: return "sphere";
  }
  return "?";
}

std::vector<std::string> builtin_module_names() {
  std::vector<std::string> out;
  for (const auto& b : kBuiltins) out.emplace_back(b.name);
  return out;
}

ModuleDef builtin_module_def(const std::string& name) {
  for (const auto& b : kBuiltins)
    if (name == b.name) return b.make();
  std::ostringstream msg;
  msg << "unknown module type '" << name << "'; known types:";
  for (const auto& b : kBuiltins) msg << ' ' << b.name;
  throw std::invalid_argument(msg.str());
}

Eigen::Matrix3d body_inertia_kg_m2(const BodyDef& b) {
  const double m = b.mass_kg, r = b.radius_m, l = b.length_m;
  double ixx = 0, iyy = 0, izz = 0;
  switch (b.shape) {
    case Shape::Sphere:
      ixx = iyy = izz = 0.4 * m * r * r;
      break;
    case Shape::Cylinder:
      izz = 0.5 * m * r * r;
      ixx = iyy = m * (3.0 * r * r + l * l) / 12.0;
      break;
    case Shape::Box: {
      const Eigen::Vector3d& s = b.box_m;
      ixx = m * (s.y() * s.y() + s.z() * s.z()) / 12.0;
      iyy = m * (s.x() * s.x() + s.z() * s.z()) / 12.0;
      izz = m * (s.x() * s.x() + s.y() * s.y()) / 12.0;
      break;
    }
    case Shape::Capsule: {
      // cylinder of length l plus two hemispheres, same density
      const double vc = kPi * r * r * l, vs = 4.0 / 3.0 * kPi * r * r * r;
      const double mc = m * vc / (vc + vs), ms = m * vs / (vc + vs);
      izz = mc * r * r / 2.0 + ms * 0.4 * r * r;
      // each hemisphere: own centroid 3r/8 from its flat face, which is l/2 from the centre
      ixx = iyy = mc * (r * r / 4.0 + l * l / 12.0) +
                  ms * (0.4 * r * r + 0.375 * r * l + 0.25 * l * l);
      break;
    }
  }
  Eigen::Matrix3d i = Eigen::Matrix3d::Zero();
  i.diagonal() << ixx, iyy, izz;
  return i;
}

double module_mass_kg(const ModuleDef& def) {
  double m = 0;
  for (const auto& b : def.bodies) m += b.mass_kg;
  return m;
}

std::vector<int> driven_servo_actuators(const ModuleDef& def) {
  std::vector<int> out;
  for (int a = 0; a < static_cast<int>(def.actuators.size()); ++a)
    if (def.actuators[a].type == ActuatorType::Servo && def.actuators[a].follows < 0)
      out.push_back(a);
  return out;
}

void validate_module_def(const ModuleDef& d) {
  const int nb = static_cast<int>(d.bodies.size());
  const int nj = static_cast<int>(d.joints.size());
  const int na = static_cast<int>(d.actuators.size());
  if (d.type.empty()) invalid(d, "empty type name");
  if (nb == 0) invalid(d, "no bodies");
  std::set<std::string> names;
  for (const auto& b : d.bodies) {
    if (b.name.empty()) invalid(d, "a body has no name");
    if (!names.insert(b.name).second) invalid(d, "duplicate body name '" + b.name + "'");
    if (!(b.mass_kg > 0)) invalid(d, "body '" + b.name + "': mass must be > 0");
    if (!finite(b.pose.position) || !b.pose.orientation.coeffs().allFinite() ||
        std::fabs(b.pose.orientation.norm() - 1.0) > 1e-6)
      invalid(d, "body '" + b.name + "': bad pose (orientation must be a unit quaternion)");
    switch (b.shape) {
      case Shape::Sphere:
        if (!(b.radius_m > 0)) invalid(d, "body '" + b.name + "': radius must be > 0");
        break;
      case Shape::Cylinder:
        if (!(b.radius_m > 0) || !(b.length_m > 0))
          invalid(d, "body '" + b.name + "': cylinder radius and length must be > 0");
        break;
      case Shape::Capsule:
        if (!(b.radius_m > 0) || !(b.length_m >= 0))
          invalid(d, "body '" + b.name + "': capsule radius must be > 0 and length >= 0");
        break;
      case Shape::Box:
        if (!(b.box_m.minCoeff() > 0)) invalid(d, "body '" + b.name + "': box sides must be > 0");
        break;
    }
  }
  auto body_ok = [&](int i) { return i >= 0 && i < nb; };
  for (const auto& j : d.joints) {
    if (!body_ok(j.parent) || !body_ok(j.child) || j.parent == j.child)
      invalid(d, "joint '" + j.name + "': parent/child must be two different body indices");
    if (j.type != JointType::Fixed && !(j.axis.norm() > 1e-9 && finite(j.axis)))
      invalid(d, "joint '" + j.name + "': zero axis");
    if (!finite(j.anchor_m)) invalid(d, "joint '" + j.name + "': bad anchor");
    if (!(j.lo <= j.hi)) invalid(d, "joint '" + j.name + "': lo > hi");
    if (j.type == JointType::Hinge && ((std::isfinite(j.lo) && j.lo < -kPi) ||
                                       (std::isfinite(j.hi) && j.hi > kPi)))
      invalid(d, "joint '" + j.name + "': hinge limits must be within [-pi, pi]");
  }
  for (int a = 0; a < na; ++a) {
    const auto& act = d.actuators[a];
    const bool joint_ok = act.joint >= 0 && act.joint < nj;
    switch (act.type) {
      case ActuatorType::Servo:
        if (!joint_ok || d.joints[act.joint].type != JointType::Hinge)
          invalid(d, "actuator '" + act.name + "': a servo needs a hinge joint");
        if (act.follows >= na || act.follows == a ||
            (act.follows >= 0 && d.actuators[act.follows].type != ActuatorType::Servo))
          invalid(d, "actuator '" + act.name + "': 'follows' must name another servo");
        break;
      case ActuatorType::LinearServo:
        if (!joint_ok || d.joints[act.joint].type != JointType::Slider)
          invalid(d, "actuator '" + act.name + "': a linear servo needs a slider joint");
        break;
      case ActuatorType::ScrewDrive:
        if (!body_ok(act.body)) invalid(d, "actuator '" + act.name + "': bad body");
        break;
    }
  }
  for (const auto& s : d.sensors) {
    switch (s.type) {
      case SensorType::MotorCurrent:
        if (s.actuator < 0 || s.actuator >= na ||
            d.actuators[s.actuator].type != ActuatorType::Servo)
          invalid(d, "sensor '" + s.name + "': needs a servo actuator");
        if (s.channel < 0 || s.channel >= 8)
          invalid(d, "sensor '" + s.name + "': ADC channel must be 0..7");
        break;
      case SensorType::Touch:
        if (!body_ok(s.body)) invalid(d, "sensor '" + s.name + "': bad body");
        if (s.channel < 0 || s.channel >= 16)
          invalid(d, "sensor '" + s.name + "': digital input bit must be 0..15");
        break;
      case SensorType::Accelerometer:
        if (!body_ok(s.body)) invalid(d, "sensor '" + s.name + "': bad body");
        break;
      case SensorType::WheelEncoder:
        if (s.joint < 0 || s.joint >= nj) invalid(d, "sensor '" + s.name + "': bad joint");
        if (s.channel < 0 || s.channel >= 4)
          invalid(d, "sensor '" + s.name + "': counter must be 0..3");
        break;
    }
  }
  if (driven_servo_actuators(d).size() > 4) invalid(d, "more than 4 driven servos");
  if (!body_ok(d.front.body) || !body_ok(d.back.body))
    invalid(d, "docking faces must name bodies");
}

}  // namespace chainsim
