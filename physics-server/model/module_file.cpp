// Module definition files (module_file.h; the format: docs/module-format.md).
// Names refer to bodies, joints and actuators; the parser resolves them to
// the indices a ModuleDef holds and reports every problem it can place at the
// YAML node at fault. validate_module_def runs last as a backstop.
#include "model/module_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <set>

#include "readers/strict_yaml.h"
#include "model/units.h"

namespace chainsim {
namespace {

constexpr double kBig = 1e6;  // bound for sizes and positions (m), forces (N), ...
// bounds of a module type's lists, counted before any entry is read (the
// shipped types have at most 5 bodies; a chain is at most 64 modules)
constexpr size_t kMaxBodies = 32;
constexpr size_t kMaxJoints = 32;
constexpr size_t kMaxActuators = 16;
constexpr size_t kMaxSensors = 32;
constexpr size_t kMaxWheelSets = 8;
constexpr size_t kMaxPads = 8;

using Keys = std::set<std::string>;

bool is_identifier(const std::string& s) {
  if (s.empty() || s.size() > 63) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

// name -> index within one section of the file, with the list for messages
struct Names {
  const char* kind;    // "body", "joint", "actuator"
  const char* plural;  // "bodies", ...
  size_t limit;        // most entries a module type may have
  std::map<std::string, int> index;
  std::vector<std::string> order;
  std::string list() const {
    std::string out;
    for (const auto& n : order) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
  }
};

class Parser {
 public:
  explicit Parser(const StrictYaml& y) : y_(y) {}

  ModuleDef parse(const YAML::Node& root) {
    if (!root || !root.IsMap()) fail(root, "a module definition must be a YAML mapping");
    check_keys(root, "module",
               {"type", "description", "bodies", "joints", "actuators", "sensors", "wheels",
                "pads", "docking"});
    ModuleDef d;
    if (!root["type"]) fail(root, "missing key 'type' (the module type's name)");
    d.type = name_of(root["type"], "type");
    if (const YAML::Node n = root["description"]) d.description = string_of(n, "description");

    const YAML::Node bodies = root["bodies"];
    if (!bodies) fail(root, "missing key 'bodies' (a list of at least one body)");
    const YAML::Node joints = root["joints"];
    const YAML::Node actuators = root["actuators"];
    const YAML::Node sensors = root["sensors"];
    // names first, so that any entry may refer to any other
    collect(bodies, "bodies", &bodies_);
    collect(joints, "joints", &joints_);
    collect(actuators, "actuators", &actuators_);
    if (bodies_.order.empty()) fail(bodies, "'bodies' is empty: a module needs at least one body");
    if (sensors && !sensors.IsSequence()) fail(sensors, "'sensors' must be a list");
    bounded(sensors, "sensors", kMaxSensors, "sensors");

    for (size_t i = 0; i < bodies.size(); ++i)
      d.bodies.push_back(body(bodies[i], "bodies[" + std::to_string(i) + "]"));
    for (size_t i = 0; joints && i < joints.size(); ++i)
      d.joints.push_back(joint(joints[i], "joints[" + std::to_string(i) + "]"));
    joined(d, bodies);
    for (size_t i = 0; actuators && i < actuators.size(); ++i)
      d.actuators.push_back(
          actuator(actuators[i], "actuators[" + std::to_string(i) + "]", d, static_cast<int>(i)));
    for (size_t i = 0; i < d.actuators.size(); ++i) {
      const int f = d.actuators[i].follows;
      if (f >= 0 && (d.actuators[f].type != ActuatorType::Servo || d.actuators[f].follows >= 0))
        fail(actuators[i]["follows"], "'actuators[" + std::to_string(i) + "].follows': '" +
                                          d.actuators[f].name +
                                          "' is not a servo with its own set-point");
    }
    std::set<std::string> sensor_names;
    for (size_t i = 0; sensors && i < sensors.size(); ++i) {
      const std::string p = "sensors[" + std::to_string(i) + "]";
      d.sensors.push_back(sensor(sensors[i], p, d));
      if (!sensor_names.insert(d.sensors.back().name).second)
        fail(sensors[i]["name"],
             "'" + p + ".name': duplicate sensor name '" + d.sensors.back().name + "'");
    }

    if (const YAML::Node wheels = root["wheels"]) {
      if (!wheels.IsSequence()) fail(wheels, "'wheels' must be a list");
      bounded(wheels, "wheels", kMaxWheelSets, "wheel sets");
      std::set<std::string> names;
      for (size_t i = 0; i < wheels.size(); ++i) {
        const std::string p = "wheels[" + std::to_string(i) + "]";
        d.wheels.push_back(wheel_set(wheels[i], p));
        if (!names.insert(d.wheels.back().name).second)
          fail(wheels[i]["name"], "'" + p + ".name': duplicate wheel set name '" +
                                      d.wheels.back().name + "'");
      }
    }

    if (const YAML::Node pads = root["pads"]) {
      if (!pads.IsSequence()) fail(pads, "'pads' must be a list");
      bounded(pads, "pads", kMaxPads, "pads");
      std::set<std::string> names;
      for (const WheelSetDef& w : d.wheels) names.insert(w.name);
      for (size_t i = 0; i < pads.size(); ++i) {
        const std::string p = "pads[" + std::to_string(i) + "]";
        d.pads.push_back(pad(pads[i], p));
        if (!names.insert(d.pads.back().name).second)
          fail(pads[i]["name"], "'" + p + ".name': duplicate wheel set or pad name '" +
                                    d.pads.back().name + "'");
      }
    }

    const YAML::Node dock = root["docking"];
    if (!dock) fail(root, "missing key 'docking' (front and back faces)");
    check_keys(dock, "docking", {"front", "back"});
    if (!dock["front"]) fail(dock, "missing key 'docking.front'");
    if (!dock["back"]) fail(dock, "missing key 'docking.back'");
    d.front = face(dock["front"], "docking.front");
    d.back = face(dock["back"], "docking.back");

    try {
      validate_module_def(d);
    } catch (const std::invalid_argument& e) {
      fail(root, e.what());
    }
    return d;
  }

 private:
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const { y_.fail(n, what); }

  void check_keys(const YAML::Node& map, const std::string& path, const Keys& allowed) const {
    y_.keys(map, path, allowed);
  }

  // after check_keys with all of a section's keys: the keys this entry's type uses
  void check_used(const YAML::Node& map, const std::string& path, const Keys& used,
                  const std::string& what) const {
    for (const auto& kv : map) {
      const std::string key = kv.first.as<std::string>();
      if (!used.count(key))
        fail(kv.first, "'" + path + "." + key + "' does not apply to " + what +
                           " (its keys: " + join_names(used) + ")");
    }
  }

  YAML::Node need(const YAML::Node& map, const std::string& key, const std::string& path,
                  const std::string& what = "") const {
    const YAML::Node n = map[key];
    if (!n)
      fail(map, "'" + path + "' needs '" + key + "'" + (what.empty() ? "" : " (" + what + ")"));
    return n;
  }

  std::string string_of(const YAML::Node& n, const std::string& path) const { return y_.string_at(n, path); }

  std::string name_of(const YAML::Node& n, const std::string& path) const {
    const std::string s = string_of(n, path);
    if (!is_identifier(s))
      fail(n, "'" + path + "' = '" + s + "' must be 1 to 63 letters, digits, '_' or '-'");
    return s;
  }

  double number(const YAML::Node& n, const std::string& path, double lo, double hi) const {
    return y_.number_at(n, path, lo, hi);
  }

  double number(const YAML::Node& map, const std::string& key, const std::string& path, double dflt,
                double lo, double hi) const {
    return y_.number(map, key, dflt, lo, hi, path);
  }

  int integer(const YAML::Node& map, const std::string& key, const std::string& path, int dflt,
              int lo, int hi) const {
    return static_cast<int>(y_.integer(map, key, dflt, lo, hi, path));
  }

  std::vector<double> numbers(const YAML::Node& n, const std::string& path, size_t count,
                              const char* form) const {
    if (!n.IsSequence() || n.size() != count)
      fail(n, "'" + path + "' must be a list of " + std::to_string(count) + " numbers " + form);
    std::vector<double> out;
    for (size_t i = 0; i < count; ++i)
      out.push_back(number(n[i], path + "[" + std::to_string(i) + "]", -kBig, kBig));
    return out;
  }

  Eigen::Vector3d vec3(const YAML::Node& n, const std::string& path) const {
    const std::vector<double> v = numbers(n, path, 3, "[x, y, z]");
    return Eigen::Vector3d(v[0], v[1], v[2]);
  }

  Eigen::Vector3d direction(const YAML::Node& n, const std::string& path) const {
    const Eigen::Vector3d v = vec3(n, path);
    if (!(v.norm() > 1e-9)) fail(n, "'" + path + "' must not be the zero vector");
    return v;
  }

  // `rotation: {axis: [x, y, z], angle_deg: a}` or `quaternion_wxyz: [w, x, y, z]`
  Eigen::Quaterniond orientation(const YAML::Node& map, const std::string& path) const {
    const YAML::Node r = map["rotation"];
    const YAML::Node q = map["quaternion_wxyz"];
    if (r && q) fail(q, "'" + path + "' has both 'rotation' and 'quaternion_wxyz'; give one");
    if (r) {
      const std::string p = path + ".rotation";
      check_keys(r, p, {"axis", "angle_deg"});
      const Eigen::Vector3d axis = direction(need(r, "axis", p, "[x, y, z]"), p + ".axis");
      const double deg = number(need(r, "angle_deg", p), p + ".angle_deg", -360.0, 360.0);
      return Eigen::Quaterniond(Eigen::AngleAxisd(deg * kPi / 180.0, axis.normalized()));
    }
    if (q) {
      const std::vector<double> v = numbers(q, path + ".quaternion_wxyz", 4, "[w, x, y, z]");
      Eigen::Quaterniond out(v[0], v[1], v[2], v[3]);
      if (std::fabs(out.norm() - 1.0) > 1e-3)
        fail(q, "'" + path + ".quaternion_wxyz' is not a unit quaternion");
      return out.normalized();
    }
    return Eigen::Quaterniond::Identity();
  }

  int ref(const YAML::Node& map, const std::string& key, const std::string& path,
          const Names& names) const {
    const YAML::Node n = need(map, key, path, std::string("a ") + names.kind + " name");
    const std::string s = string_of(n, path + "." + key);
    const auto it = names.index.find(s);
    if (it == names.index.end())
      fail(n, "'" + path + "." + key + "': no " + names.kind + " '" + s + "' in this module (" +
                  names.plural + ": " + names.list() + ")");
    return it->second;
  }

  // list (a sequence) has at most limit entries: "'bodies' has 40 bodies, more than the limit of 32"
  void bounded(const YAML::Node& list, const std::string& path, size_t limit, const char* plural) const {
    if (list && list.IsSequence() && list.size() > limit)
      fail(list, "'" + path + "' has " + std::to_string(list.size()) + " " + plural + ", more than the limit of " +
                     std::to_string(limit));
  }

  void collect(const YAML::Node& list, const std::string& path, Names* names) const {
    if (!list) return;
    if (!list.IsSequence()) fail(list, "'" + path + "' must be a list");
    bounded(list, path, names->limit, names->plural);
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string p = path + "[" + std::to_string(i) + "]";
      if (!list[i].IsMap()) fail(list[i], "'" + p + "' must be a mapping");
      const std::string name = name_of(need(list[i], "name", p), p + ".name");
      if (!names->index.emplace(name, static_cast<int>(i)).second)
        fail(list[i]["name"],
             "'" + p + ".name': duplicate " + names->kind + " name '" + name + "'");
      names->order.push_back(name);
    }
  }

  BodyDef body(const YAML::Node& n, const std::string& p) const {
    static const Keys kCommon = {"name",     "shape",           "mass_kg", "position_m",
                                 "rotation", "quaternion_wxyz", "collide"};
    Keys all = kCommon;
    all.insert({"radius_m", "length_m", "size_m"});
    check_keys(n, p, all);
    BodyDef b;
    b.name = n["name"].as<std::string>();
    const YAML::Node shape = need(n, "shape", p, "capsule, cylinder, box or sphere");
    const std::string s = string_of(shape, p + ".shape");
    Keys used = kCommon;
    if (s == "capsule" || s == "cylinder") {
      b.shape = s == "capsule" ? Shape::Capsule : Shape::Cylinder;
      used.insert({"radius_m", "length_m"});
    } else if (s == "sphere") {
      b.shape = Shape::Sphere;
      used.insert("radius_m");
    } else if (s == "box") {
      b.shape = Shape::Box;
      used.insert("size_m");
    } else {
      fail(shape, "'" + p + ".shape' = '" + s +
                      "' is not a shape (known: box, capsule, cylinder, sphere)");
    }
    check_used(n, p, used, "a " + s);
    b.mass_kg = number(need(n, "mass_kg", p), p + ".mass_kg", 1e-9, kBig);
    if (b.mass_kg <= 0) fail(n["mass_kg"], "'" + p + ".mass_kg' must be > 0");
    switch (b.shape) {
      case Shape::Capsule:
        b.radius_m = number(need(n, "radius_m", p), p + ".radius_m", 1e-6, kBig);
        // ODE's convention: the straight part only; 0 = a sphere
        b.length_m = number(need(n, "length_m", p, "the straight part"), p + ".length_m", 0, kBig);
        break;
      case Shape::Cylinder:
        b.radius_m = number(need(n, "radius_m", p), p + ".radius_m", 1e-6, kBig);
        b.length_m = number(need(n, "length_m", p), p + ".length_m", 1e-6, kBig);
        break;
      case Shape::Sphere:
        b.radius_m = number(need(n, "radius_m", p), p + ".radius_m", 1e-6, kBig);
        break;
      case Shape::Box: {
        const YAML::Node sz = need(n, "size_m", p, "[x, y, z]");
        b.box_m = vec3(sz, p + ".size_m");
        if (!(b.box_m.minCoeff() >= 1e-6)) fail(sz, "'" + p + ".size_m': box sides must be > 0");
        break;
      }
    }
    if (const YAML::Node pos = n["position_m"]) b.pose.position = vec3(pos, p + ".position_m");
    b.pose.orientation = orientation(n, p);
    if (const YAML::Node c = n["collide"]) {
      if (!c.IsScalar() || (c.as<std::string>() != "true" && c.as<std::string>() != "false"))
        fail(c, "'" + p + ".collide' must be true or false");
      b.collides = c.as<std::string>() == "true";
    }
    return b;
  }

  // every body reachable from the first through the joints: a body joined
  // to nothing would fall away from its module
  void joined(const ModuleDef& d, const YAML::Node& bodies) const {
    std::vector<char> reached(d.bodies.size(), 0);
    reached[0] = 1;
    for (bool grew = true; grew;) {
      grew = false;
      for (const JointDef& j : d.joints)
        if (reached[j.parent] != reached[j.child]) reached[j.parent] = reached[j.child] = 1, grew = true;
    }
    for (size_t b = 0; b < d.bodies.size(); ++b)
      if (!reached[b])
        fail(bodies[b], "'bodies[" + std::to_string(b) + "]' ('" + d.bodies[b].name + "') is not joined to '" +
                            d.bodies[0].name + "' through 'joints': every body of a module must be (a fixed "
                            "joint where it does not move)");
  }

  JointDef joint(const YAML::Node& n, const std::string& p) const {
    check_keys(n, p,
               {"name", "type", "parent", "child", "anchor_m", "axis", "limits_deg", "limits_m",
                "friction_nm_s_rad"});
    JointDef j;
    j.name = n["name"].as<std::string>();
    const YAML::Node type = need(n, "type", p, "hinge, slider or fixed");
    const std::string t = string_of(type, p + ".type");
    Keys used = {"name", "type", "parent", "child"};
    if (t == "hinge") {
      j.type = JointType::Hinge;
      used.insert({"anchor_m", "axis", "limits_deg", "friction_nm_s_rad"});
    } else if (t == "slider") {
      j.type = JointType::Slider;
      used.insert({"axis", "limits_m"});
    } else if (t == "fixed") {
      j.type = JointType::Fixed;
    } else {
      fail(type,
           "'" + p + ".type' = '" + t + "' is not a joint type (known: fixed, hinge, slider)");
    }
    check_used(n, p, used, "a " + t + " joint");
    j.parent = ref(n, "parent", p, bodies_);
    j.child = ref(n, "child", p, bodies_);
    if (j.parent == j.child) fail(n["child"], "'" + p + "': parent and child are the same body");
    if (j.type == JointType::Hinge) {
      j.anchor_m = vec3(need(n, "anchor_m", p, "[x, y, z] in the module frame"), p + ".anchor_m");
      j.axis = direction(need(n, "axis", p, "[x, y, z] in the module frame"), p + ".axis");
      if (const YAML::Node l = n["limits_deg"]) {
        const std::vector<double> v = numbers(l, p + ".limits_deg", 2, "[lo, hi]");
        if (v[0] < -180 || v[1] > 180 || v[0] > v[1])
          fail(l, "'" + p + ".limits_deg' must be [lo, hi] with -180 <= lo <= hi <= 180");
        j.lo = v[0] * kPi / 180.0;
        j.hi = v[1] * kPi / 180.0;
      }
      j.friction_nm_s_rad = number(n, "friction_nm_s_rad", p, 0.0, 0.0, kBig);
    } else if (j.type == JointType::Slider) {
      j.axis = direction(need(n, "axis", p, "[x, y, z] in the module frame"), p + ".axis");
      if (const YAML::Node l = n["limits_m"]) {
        const std::vector<double> v = numbers(l, p + ".limits_m", 2, "[lo, hi]");
        if (v[0] > v[1]) fail(l, "'" + p + ".limits_m' must be [lo, hi] with lo <= hi");
        j.lo = v[0];
        j.hi = v[1];
      }
    }
    return j;
  }

  ServoParams servo_params(const YAML::Node& n, const std::string& p) const {
    struct Field {
      const char* key;
      double ServoParams::*member;
      double lo;
    };
    static const Field kFields[] = {
        {"kp", &ServoParams::kp, 0},
        {"km", &ServoParams::km, 0},
        {"kt", &ServoParams::kt, 0},
        {"r", &ServoParams::r, 1e-9},
        {"l", &ServoParams::l, 1e-12},
        {"b", &ServoParams::b, 0},
        {"j", &ServoParams::j, 0},
        {"supply_v", &ServoParams::supply_v, 0},
        {"current_filter_tau_s", &ServoParams::current_filter_tau_s, 0},
        {"i_threshold_a", &ServoParams::i_threshold_a, 0},
        {"adc_full_scale_a", &ServoParams::adc_full_scale_a, 1e-9},
        // the calibration effect catalogue (servo_model.h), 0 = off
        {"coulomb_nm", &ServoParams::coulomb_nm, 0},
        {"backlash_deg", &ServoParams::backlash_deg, 0},
        {"deadband_deg", &ServoParams::deadband_deg, 0},
        {"supply_sag_ohm", &ServoParams::supply_sag_ohm, 0},
        {"pwm_frame_s", &ServoParams::pwm_frame_s, 0},
        {"current_limit_a", &ServoParams::current_limit_a, 0},
        {"pwm_frame_phase_s", &ServoParams::pwm_frame_phase_s, 0},
        {"supply_sag_linear_ohm", &ServoParams::supply_sag_linear_ohm, 0},
        {"backlash_stiffness_nm_rad", &ServoParams::backlash_stiffness_nm_rad, 0},
        {"supply_rail_f", &ServoParams::supply_rail_f, 0},
        {"pwm_pulse_s_per_deg", &ServoParams::pwm_pulse_s_per_deg, 0},
        {"deadband_comparator_deg", &ServoParams::deadband_comparator_deg, 0},
    };
    Keys keys;
    for (const Field& f : kFields) keys.insert(f.key);
    check_keys(n, p, keys);
    ServoParams s;  // the paper's Table 1, then the file's overrides
    for (const Field& f : kFields)
      s.*f.member = number(n, f.key, p, s.*f.member, f.lo,
                           f.member == &ServoParams::pwm_pulse_s_per_deg ? kMaxPulseSPerDeg : kBig);
    if (const std::string why = servo_params_conflict(s); !why.empty()) fail(n, "'" + p + "': " + why);
    return s;
  }

  ActuatorDef actuator(const YAML::Node& n, const std::string& p, const ModuleDef& d,
                       int index) const {
    check_keys(n, p,
               {"name", "type", "joint", "body", "follows", "servo", "fmax_n", "l0_m", "direction",
                "v_free_m_s", "stall_current_a", "stall_torque_nm", "free_speed_rad_s"});
    ActuatorDef a;
    a.name = n["name"].as<std::string>();
    const YAML::Node type = need(n, "type", p, "servo, linear_servo, screw_drive or dc_motor");
    const std::string t = string_of(type, p + ".type");
    Keys used = {"name", "type"};
    const Keys force = {"fmax_n", "v_free_m_s", "stall_current_a"};
    if (t == "servo") {
      a.type = ActuatorType::Servo;
      used.insert({"joint", "follows", "servo"});
    } else if (t == "linear_servo") {
      a.type = ActuatorType::LinearServo;
      used.insert({"joint", "l0_m"});
      used.insert(force.begin(), force.end());
    } else if (t == "screw_drive") {
      a.type = ActuatorType::ScrewDrive;
      used.insert({"body", "direction"});
      used.insert(force.begin(), force.end());
    } else if (t == "dc_motor") {
      a.type = ActuatorType::DcMotor;
      used.insert({"joint", "stall_torque_nm", "free_speed_rad_s", "stall_current_a"});
    } else {
      fail(type, "'" + p + ".type' = '" + t +
                     "' is not an actuator type (known: dc_motor, linear_servo, screw_drive, "
                     "servo)");
    }
    check_used(n, p, used, "a " + t);
    if (a.type != ActuatorType::ScrewDrive) {
      a.joint = ref(n, "joint", p, joints_);
      const JointType want =
          a.type == ActuatorType::LinearServo ? JointType::Slider : JointType::Hinge;
      if (d.joints[a.joint].type != want)
        fail(n["joint"], "'" + p + ".joint': a " + t + " needs a " +
                             (want == JointType::Hinge ? "hinge" : "slider") + " joint");
    }
    if (a.type == ActuatorType::Servo) {
      if (n["follows"]) {
        a.follows = ref(n, "follows", p, actuators_);
        if (a.follows == index)
          fail(n["follows"], "'" + p + ".follows': a servo cannot follow itself");
      }
      if (const YAML::Node s = n["servo"]) a.servo = servo_params(s, p + ".servo");
    } else if (a.type == ActuatorType::DcMotor) {
      // the force law's fields, in torque units (module_def.h)
      a.fmax_n = number(need(n, "stall_torque_nm", p, "N m"), p + ".stall_torque_nm", 1e-12, kBig);
      a.v_free_m_s =
          number(need(n, "free_speed_rad_s", p, "rad/s"), p + ".free_speed_rad_s", 1e-9, kBig);
      a.stall_current_a = number(n, "stall_current_a", p, 0.0, 0.0, kBig);
    } else {
      a.fmax_n = number(need(n, "fmax_n", p, "N"), p + ".fmax_n", 1e-9, kBig);
      a.v_free_m_s = number(n, "v_free_m_s", p, 0.0, 0.0, kBig);
      a.stall_current_a = number(n, "stall_current_a", p, 0.0, 0.0, kBig);
      if (a.type == ActuatorType::LinearServo) {
        a.l0_m = number(need(n, "l0_m", p, "m"), p + ".l0_m", 1e-9, kBig);
      } else {
        a.body = ref(n, "body", p, bodies_);
        a.direction =
            direction(need(n, "direction", p, "[x, y, z] in the body frame"), p + ".direction");
      }
    }
    return a;
  }

  SensorDef sensor(const YAML::Node& n, const std::string& p, const ModuleDef& d) const {
    if (!n.IsMap()) fail(n, "'" + p + "' must be a mapping");
    check_keys(n, p,
               {"name", "type", "actuator", "body", "joint", "channel", "range_g", "noise_g",
                "bandwidth_hz", "rotation", "quaternion_wxyz", "counts_per_rev", "sectors", "first_deg",
                "half_width_deg"});
    SensorDef s;
    s.name = name_of(need(n, "name", p), p + ".name");
    const YAML::Node type =
        need(n, "type", p, "motor_current, touch, accelerometer or wheel_encoder");
    const std::string t = string_of(type, p + ".type");
    Keys used = {"name", "type", "channel"};
    if (t == "motor_current") {
      s.type = SensorType::MotorCurrent;
      used.insert("actuator");
    } else if (t == "touch") {
      s.type = SensorType::Touch;
      used.insert({"body", "sectors", "first_deg", "half_width_deg"});
    } else if (t == "accelerometer") {
      s.type = SensorType::Accelerometer;
      used.insert({"body", "range_g", "noise_g", "bandwidth_hz", "rotation", "quaternion_wxyz"});
    } else if (t == "wheel_encoder") {
      s.type = SensorType::WheelEncoder;
      used.insert({"joint", "counts_per_rev"});
    } else {
      fail(type, "'" + p + ".type' = '" + t +
                     "' is not a sensor type (known: accelerometer, motor_current, touch, "
                     "wheel_encoder)");
    }
    check_used(n, p, used, "a " + t + " sensor");
    need(n, "channel", p, "ADC channel, input bit or counter");
    switch (s.type) {
      case SensorType::MotorCurrent:
        s.actuator = ref(n, "actuator", p, actuators_);
        s.channel = integer(n, "channel", p, 0, 0, 7);
        break;
      case SensorType::Touch:
        s.body = ref(n, "body", p, bodies_);
        s.channel = integer(n, "channel", p, 0, 0, 15);
        s.sectors = integer(n, "sectors", p, 1, 1, 8);
        s.first_deg = number(n, "first_deg", p, 0.0, -360.0, 360.0);
        s.half_width_deg = number(n, "half_width_deg", p, 180.0 / s.sectors, 1.0, 180.0);
        break;
      case SensorType::Accelerometer:
        s.body = ref(n, "body", p, bodies_);
        s.channel = integer(n, "channel", p, 0, 0, 5);  // uses channel .. channel + 2
        s.range_g = number(n, "range_g", p, s.range_g, 1e-3, 1000.0);
        s.noise_g = number(n, "noise_g", p, s.noise_g, 0.0, 1000.0);
        s.bandwidth_hz = number(n, "bandwidth_hz", p, s.bandwidth_hz, 0.0, 1e9);
        s.orientation = orientation(n, p);
        break;
      case SensorType::WheelEncoder:
        s.joint = ref(n, "joint", p, joints_);
        if (d.joints[s.joint].type != JointType::Hinge)
          fail(n["joint"], "'" + p + ".joint': a wheel encoder needs a hinge joint");
        s.channel = integer(n, "channel", p, 0, 0, 3);
        s.counts_per_rev = integer(n, "counts_per_rev", p, s.counts_per_rev, 1, 1 << 24);
        break;
    }
    return s;
  }

  // a ring of spring-loaded wheels (model/wheel_def.h)
  WheelSetDef wheel_set(const YAML::Node& n, const std::string& p) const {
    if (!n.IsMap()) fail(n, "'" + p + "' must be a mapping");
    check_keys(n, p,
               {"name", "body", "count", "first_deg", "x_m", "helix_deg", "reach_m", "preload_n",
                "stiffness_n_m", "damping_n_s_m", "mu", "cornering_per_rad"});
    WheelSetDef w;
    w.name = name_of(need(n, "name", p), p + ".name");
    w.body = ref(n, "body", p, bodies_);
    w.count = integer(n, "count", p, w.count, 1, 16);
    w.first_deg = number(n, "first_deg", p, w.first_deg, -360.0, 360.0);
    w.x_m = number(need(n, "x_m", p, "m, on the module's x axis"), p + ".x_m", -kBig, kBig);
    w.helix_deg = number(n, "helix_deg", p, w.helix_deg, 0.0, 90.0);
    const YAML::Node r = need(n, "reach_m", p, "[folded, extended] from the axis");
    const std::vector<double> reach = numbers(r, p + ".reach_m", 2, "[folded, extended]");
    if (!(reach[0] > 0 && reach[0] < reach[1]))
      fail(r, "'" + p + ".reach_m' must be [min, max] with 0 < min < max");
    w.reach_min_m = reach[0];
    w.reach_max_m = reach[1];
    w.preload_n = number(need(n, "preload_n", p, "N at full extension"), p + ".preload_n", 0, kBig);
    w.stiffness_n_m =
        number(need(n, "stiffness_n_m", p, "N/m"), p + ".stiffness_n_m", 1e-9, kBig);
    w.damping_n_s_m = number(n, "damping_n_s_m", p, 0.0, 0.0, kBig);
    w.mu = number(need(n, "mu", p, "friction across the wheel"), p + ".mu", 0.0, kBig);
    w.cornering_per_rad = number(n, "cornering_per_rad", p, 0.0, 0.0, kBig);
    return w;
  }

  // a friction pad (model/wheel_def.h)
  PadDef pad(const YAML::Node& n, const std::string& p) const {
    if (!n.IsMap()) fail(n, "'" + p + "' must be a mapping");
    check_keys(n, p,
               {"name", "body", "position_m", "direction", "reach_m", "stiffness_n_m",
                "damping_n_s_m", "mu"});
    PadDef d;
    d.name = name_of(need(n, "name", p), p + ".name");
    d.body = ref(n, "body", p, bodies_);
    d.position_m = vec3(need(n, "position_m", p, "[x, y, z] in the module frame"), p + ".position_m");
    d.direction = direction(need(n, "direction", p, "[x, y, z] in the module frame"),
                            p + ".direction").normalized();
    d.reach_m = number(need(n, "reach_m", p, "m"), p + ".reach_m", 1e-9, kBig);
    d.stiffness_n_m = number(need(n, "stiffness_n_m", p, "N/m"), p + ".stiffness_n_m", 1e-9, kBig);
    d.damping_n_s_m = number(n, "damping_n_s_m", p, 0.0, 0.0, kBig);
    d.mu = number(need(n, "mu", p, "friction on the wall"), p + ".mu", 0.0, kBig);
    return d;
  }

  DockingFace face(const YAML::Node& n, const std::string& p) const {
    check_keys(n, p, {"body", "position_m", "rotation", "quaternion_wxyz"});
    DockingFace f;
    f.body = ref(n, "body", p, bodies_);
    if (const YAML::Node pos = n["position_m"]) f.frame.position = vec3(pos, p + ".position_m");
    f.frame.orientation = orientation(n, p);
    return f;
  }

  const StrictYaml& y_;
  Names bodies_{"body", "bodies", kMaxBodies, {}, {}};
  Names joints_{"joint", "joints", kMaxJoints, {}, {}};
  Names actuators_{"actuator", "actuators", kMaxActuators, {}, {}};
};

}  // namespace

ModuleDef load_module_text(const std::string& text, const std::string& file) {
  const StrictYaml y(file, [](const std::string& message) { throw ModuleFileError(message); });
  return Parser(y).parse(y.parse(text));
}

ModuleDef load_module_file(const std::string& path) {
  const StrictYaml y(path, [](const std::string& message) { throw ModuleFileError(message); });
  return Parser(y).parse(y.parse(y.read_file("module definition file")));
}

}  // namespace chainsim
