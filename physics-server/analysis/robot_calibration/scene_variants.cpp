// The scenes of a robot calibration and their variants (scene_variants.h).
#include "analysis/robot_calibration/scene_variants.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "model/module_def.h"
#include "model/module_file.h"

namespace chainsim {
namespace {

std::string replace_all(std::string s, const std::string& a, const std::string& b) {
  for (size_t p = s.find(a); p != std::string::npos; p = s.find(a, p + b.size())) s.replace(p, a.size(), b);
  return s;
}

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw RobotError(path + ": cannot read");
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// the text of a module type's definition: the scene's own file, or the built-in
std::string module_text(const YAML::Node& root, const std::string& dir, const std::string& type) {
  if (root["module_types"] && root["module_types"][type]) {
    std::filesystem::path p = root["module_types"][type].as<std::string>();
    if (p.is_relative()) p = std::filesystem::path(dir) / p;
    return read_text(p.string());
  }
  for (const auto& b : builtin_module_files())
    if (type == b.name) return b.text;
  throw RobotError("module type '" + type + "' has no definition");
}

// kt of the servo actuator a of def (its own model, else the World's)
double servo_kt(const Scene& s, const ActuatorDef& a) { return a.servo ? a.servo->kt : s.world.servo.kt; }

void write_module(const YAML::Node& def, const std::string& file) {
  YAML::Emitter e;
  e << def;
  std::ofstream f(file);
  f << e.c_str() << "\n";
  if (!f) throw RobotError(file + ": cannot write");
}

}  // namespace

SceneVariants::SceneVariants(const std::string& scene_template, const std::vector<std::string>& keys) {
  for (const std::string& key : keys) {
    const std::string path = replace_all(scene_template, "{slope}", key);
    if (!std::filesystem::exists(path))
      throw RobotError(path + ": no such scene (template " + scene_template + ", row " + key + ")");
    try {
      scenes_.push_back(load_scene_file(path));
    } catch (const SceneError& e) {
      throw RobotError(std::string(e.what()) + " (row " + key + ")");
    }
    texts_.push_back(read_text(path));
    dirs_.push_back(std::filesystem::absolute(path).parent_path().string());
  }
  const Scene& s0 = scenes_.at(0);
  chain0_ = compile_chain(s0);
  const YAML::Node root0 = YAML::Load(texts_[0]);
  nominal_[robot_knob("wall_friction")] = s0.world.ground.mu;
  if (const ModuleDef* helicoidal = chain0_.first_of_type("helicoidal")) {
    type_text_["helicoidal"] = module_text(root0, dirs_[0], "helicoidal");
    const ModuleDef& h = *helicoidal;
    for (const ActuatorDef& a : h.actuators)
      if (a.type == ActuatorType::ScrewDrive || a.type == ActuatorType::DcMotor) {
        nominal_[robot_knob("drive_stall")] = a.fmax_n;
        nominal_[robot_knob("drive_free_speed")] = a.v_free_m_s;
        break;
      }
    // the wheel knobs scale every set's own value; the nominal is the first set's
    if (!h.wheels.empty()) {
      nominal_[robot_knob("wheel_preload")] = h.wheels[0].preload_n;
      nominal_[robot_knob("wheel_friction")] = h.wheels[0].mu;
    }
  }
  if (const ModuleDef* support = chain0_.first_of_type("support")) {
    type_text_["support"] = module_text(root0, dirs_[0], "support");
    for (const ActuatorDef& a : support->actuators)
      if (a.type == ActuatorType::Servo && a.follows < 0) {
        nominal_[robot_knob("arm_grip_torque")] = servo_kt(s0, a);
        break;
      }
    if (!support->pads.empty()) nominal_[robot_knob("pad_friction")] = support->pads[0].mu;
  }
  if (const ModuleDef* extension = chain0_.first_of_type("extension")) {
    type_text_["extension"] = module_text(root0, dirs_[0], "extension");
    for (const ActuatorDef& a : extension->actuators)
      if (a.type == ActuatorType::LinearServo) {
        nominal_[robot_knob("extension_force")] = a.fmax_n;
        break;
      }
  }
  for (size_t k = 0; k < robot_knobs().size(); ++k) {
    const std::string m = robot_knobs()[k].module;
    if (!m.empty() && !type_text_.count(m)) continue;
    if (nominal(static_cast<int>(k)) > 0) usable_.push_back(static_cast<int>(k));
  }
}

double SceneVariants::nominal(int knob) const {
  const auto it = nominal_.find(knob);
  return it == nominal_.end() ? 0.0 : it->second;
}

std::string SceneVariants::scene_text(size_t i, const KnobSetting& st, const std::string& dir) const {
  YAML::Node root = YAML::Load(texts_[i]);
  const std::filesystem::path here(dirs_[i]);
  if (root["module_types"])
    for (auto kv : root["module_types"]) {
      const std::filesystem::path p = kv.second.as<std::string>();
      if (p.is_relative()) root["module_types"][kv.first.as<std::string>()] = (here / p).string();
    }
  if (root["environment"] && root["environment"]["mesh"] && root["environment"]["mesh"]["file"]) {
    const std::filesystem::path p = root["environment"]["mesh"]["file"].as<std::string>();
    if (p.is_relative()) root["environment"]["mesh"]["file"] = (here / p).string();
  }
  const int mu = robot_knob("wall_friction"), stall = robot_knob("drive_stall"),
            vfree = robot_knob("drive_free_speed"), grip = robot_knob("arm_grip_torque");
  if (st.count(mu)) root["environment"]["material"]["mu"] = st.at(mu) * nominal(mu);
  const double ft = factor_of(st, stall), fv = factor_of(st, vfree), fg = factor_of(st, grip);
  const double fp = factor_of(st, robot_knob("wheel_preload")), fm = factor_of(st, robot_knob("wheel_friction"));
  const double fpad = factor_of(st, robot_knob("pad_friction"));
  const std::string tag = std::to_string(std::hash<std::string>{}(setting_key(st)));
  if ((ft != 1.0 || fv != 1.0 || fp != 1.0 || fm != 1.0) && type_text_.count("helicoidal")) {
    YAML::Node d = YAML::Load(type_text_.at("helicoidal"));
    for (auto a : d["actuators"]) {
      const std::string t = a["type"] ? a["type"].as<std::string>() : "";
      if (t != "screw_drive" && t != "dc_motor") continue;
      a[t == "dc_motor" ? "stall_torque_nm" : "fmax_n"] = ft * nominal(stall);
      a[t == "dc_motor" ? "free_speed_rad_s" : "v_free_m_s"] = fv * nominal(vfree);
    }
    if (d["wheels"])
      for (auto w : d["wheels"]) {
        if (w["preload_n"]) w["preload_n"] = fp * w["preload_n"].as<double>();
        if (w["mu"]) w["mu"] = fm * w["mu"].as<double>();
      }
    const std::string file = dir + "/helicoidal-" + tag + ".yaml";
    write_module(d, file);
    root["module_types"]["helicoidal"] = file;
  }
  if ((fg != 1.0 || fpad != 1.0) && type_text_.count("support")) {
    const ModuleDef& def = *chain0_.first_of_type("support");  // there is one: type_text_ has it
    YAML::Node d = YAML::Load(type_text_.at("support"));
    if (d["pads"])
      for (auto p : d["pads"])
        if (p["mu"]) p["mu"] = fpad * p["mu"].as<double>();
    for (size_t k = 0; k < def.actuators.size(); ++k)
      if (def.actuators[k].type == ActuatorType::Servo)
        d["actuators"][k]["servo"]["kt"] = fg * servo_kt(scenes_[0], def.actuators[k]);
    const std::string file = dir + "/support-" + tag + ".yaml";
    write_module(d, file);
    root["module_types"]["support"] = file;
  }
  const double fx = factor_of(st, robot_knob("extension_force"));
  if (fx != 1.0 && type_text_.count("extension")) {
    YAML::Node d = YAML::Load(type_text_.at("extension"));
    for (auto a : d["actuators"])
      if (a["type"] && a["type"].as<std::string>() == "linear_servo" && a["fmax_n"])
        a["fmax_n"] = fx * a["fmax_n"].as<double>();
    const std::string file = dir + "/extension-" + tag + ".yaml";
    write_module(d, file);
    root["module_types"]["extension"] = file;
  }
  YAML::Emitter e;
  e << root;
  return e.c_str();
}

}  // namespace chainsim
