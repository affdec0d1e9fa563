// Built-in module types and ModuleDef helpers. See module_def.h. The
// built-in types are the files scenes/modules/*.yaml, compiled in
// (builtin_modules.cpp.in) and parsed on first use (module_file.h).
#include "model/module_def.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

#include "model/module_file.h"
#include "model/units.h"

namespace chainsim {

namespace {


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
  for (const BuiltinModuleFile& f : builtin_module_files()) out.push_back(f.name);
  return out;
}

ModuleDef builtin_module_def(const std::string& name) {
  // parsed once per type; a shipped file that does not parse throws here
  // (with its file:line:column) every time it is asked for
  static std::mutex mutex;
  static std::map<std::string, ModuleDef> cache;
  for (const BuiltinModuleFile& f : builtin_module_files()) {
    if (name != f.name) continue;
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache.find(name);
    if (it == cache.end()) it = cache.emplace(name, load_module_text(f.text, f.path)).first;
    return it->second;
  }
  std::ostringstream msg;
  msg << "unknown module type '" << name << "'; known types:";
  for (const BuiltinModuleFile& f : builtin_module_files()) msg << ' ' << f.name;
  throw std::invalid_argument(msg.str());
}

ModuleDef find_module_def(const std::vector<ModuleDef>& types, const std::string& name) {
  const auto it = std::find_if(types.begin(), types.end(),
                               [&](const ModuleDef& d) { return d.type == name; });
  return it != types.end() ? *it : builtin_module_def(name);
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
    if (def.actuators[a].follows < 0)
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
    if (!(j.friction_nm_s_rad >= 0) || !std::isfinite(j.friction_nm_s_rad))
      invalid(d, "joint '" + j.name + "': friction must be >= 0");
    if (j.friction_nm_s_rad > 0 && j.type != JointType::Hinge)
      invalid(d, "joint '" + j.name + "': friction is for hinges only");
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
        if (!(act.l0_m > 0) || !std::isfinite(act.l0_m))
          invalid(d, "actuator '" + act.name + "': l0_m must be > 0");
        break;
      case ActuatorType::ScrewDrive:
        if (!body_ok(act.body)) invalid(d, "actuator '" + act.name + "': bad body");
        if (!(act.direction.norm() > 1e-9 && finite(act.direction)))
          invalid(d, "actuator '" + act.name + "': zero direction");
        break;
      case ActuatorType::DcMotor:
        if (!joint_ok || d.joints[act.joint].type != JointType::Hinge)
          invalid(d, "actuator '" + act.name + "': a DC motor needs a hinge joint");
        if (!(act.v_free_m_s > 0))
          invalid(d, "actuator '" + act.name + "': a DC motor needs a free speed > 0");
        break;
    }
    if (act.type != ActuatorType::Servo) {
      if (act.follows >= 0)
        invalid(d, "actuator '" + act.name + "': only servos can follow another servo");
      if (!(act.fmax_n > 0) || !std::isfinite(act.fmax_n))
        invalid(d, "actuator '" + act.name + "': fmax_n must be > 0");
      if (!(act.v_free_m_s >= 0) || !std::isfinite(act.v_free_m_s))
        invalid(d, "actuator '" + act.name + "': v_free_m_s must be >= 0");
      if (!(act.stall_current_a >= 0) || !std::isfinite(act.stall_current_a))
        invalid(d, "actuator '" + act.name + "': stall_current_a must be >= 0");
    }
  }
  // each ADC channel, input bit and counter is wired to one sensor
  std::map<std::pair<int, int>, std::string> wired;  // (kind, channel) -> sensor
  auto wire = [&](const SensorDef& s, int kind, int channel) {
    const auto [it, fresh] = wired.emplace(std::make_pair(kind, channel), s.name);
    static const char* kKind[] = {"ADC channel", "digital input bit", "counter"};
    if (!fresh)
      invalid(d, "sensor '" + s.name + "': " + kKind[kind] + " " + std::to_string(channel) +
                     " is already used by sensor '" + it->second + "'");
  };
  for (const auto& s : d.sensors) {
    switch (s.type) {
      case SensorType::MotorCurrent: wire(s, 0, s.channel); break;
      case SensorType::Touch:
        for (int k = 0; k < s.sectors; ++k) wire(s, 1, s.channel + k);
        break;
      case SensorType::Accelerometer:
        for (int k = 0; k < 3; ++k) wire(s, 0, s.channel + k);
        break;
      case SensorType::WheelEncoder: wire(s, 2, s.channel); break;
    }
    switch (s.type) {
      case SensorType::MotorCurrent:
        if (s.actuator < 0 || s.actuator >= na)
          invalid(d, "sensor '" + s.name + "': needs an actuator");
        if (s.channel < 0 || s.channel >= 8)
          invalid(d, "sensor '" + s.name + "': ADC channel must be 0..7");
        break;
      case SensorType::Touch:
        if (!body_ok(s.body)) invalid(d, "sensor '" + s.name + "': bad body");
        if (s.sectors < 1 || s.sectors > 8) invalid(d, "sensor '" + s.name + "': sectors must be 1..8");
        if (s.channel < 0 || s.channel + s.sectors > 16)
          invalid(d, "sensor '" + s.name + "': digital input bits must be within 0..15 (first " +
                         std::to_string(s.channel) + ", " + std::to_string(s.sectors) + " sectors)");
        if (!(s.half_width_deg > 0 && s.half_width_deg <= 180))
          invalid(d, "sensor '" + s.name + "': half_width_deg must be in (0, 180]");
        break;
      case SensorType::Accelerometer:
        if (!body_ok(s.body)) invalid(d, "sensor '" + s.name + "': bad body");
        if (s.channel < 0 || s.channel > 5)
          invalid(d, "sensor '" + s.name + "': first ADC channel must be 0..5 (it uses 3)");
        if (!(s.range_g > 0) || !std::isfinite(s.range_g))
          invalid(d, "sensor '" + s.name + "': range_g must be > 0");
        if (!(s.noise_g >= 0) || !std::isfinite(s.noise_g))
          invalid(d, "sensor '" + s.name + "': noise_g must be >= 0");
        if (!(s.bandwidth_hz >= 0) || !std::isfinite(s.bandwidth_hz))
          invalid(d, "sensor '" + s.name + "': bandwidth_hz must be >= 0");
        if (!s.orientation.coeffs().allFinite() || std::fabs(s.orientation.norm() - 1.0) > 1e-6)
          invalid(d, "sensor '" + s.name + "': orientation must be a unit quaternion");
        break;
      case SensorType::WheelEncoder:
        if (s.joint < 0 || s.joint >= nj || d.joints[s.joint].type != JointType::Hinge)
          invalid(d, "sensor '" + s.name + "': a wheel encoder needs a hinge joint");
        if (s.channel < 0 || s.channel >= 4)
          invalid(d, "sensor '" + s.name + "': counter must be 0..3");
        if (s.counts_per_rev < 1)
          invalid(d, "sensor '" + s.name + "': counts_per_rev must be >= 1");
        break;
    }
  }
  std::set<std::string> wheel_names;
  for (const auto& w : d.wheels) {
    try {
      validate_wheel_set(w, nb);
    } catch (const std::invalid_argument& e) {
      invalid(d, e.what());
    }
    if (!wheel_names.insert(w.name).second) invalid(d, "duplicate wheel set name '" + w.name + "'");
  }
  for (const auto& p : d.pads) {
    try {
      validate_pad(p, nb);
    } catch (const std::invalid_argument& e) {
      invalid(d, e.what());
    }
    if (!wheel_names.insert(p.name).second) invalid(d, "duplicate wheel set or pad name '" + p.name + "'");
  }
  if (driven_servo_actuators(d).size() > 4) invalid(d, "more than 4 driven servos");
  if (!body_ok(d.front.body) || !body_ok(d.back.body))
    invalid(d, "docking faces must name bodies");
}

}  // namespace chainsim
