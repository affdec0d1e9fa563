#include "output/scene_json.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/module_def.h"
#include "output/environment_json.h"

namespace chainsim {

const char* module_color(const std::string& type) {
  if (type == "rotation") return "#e4572e";
  if (type == "helicoidal") return "#29335c";
  if (type == "support") return "#f3a712";
  if (type == "extension") return "#669bbc";
  if (type == "touch") return "#a8c686";
  if (type == "traveller") return "#8e5572";
  if (type == "passive") return "#9a9a9a";
  return nullptr;
}

// the colour of each module: its type's own, or for a type of the user's the
// next of a palette apart from the shipped types' colours, in the order the
// chain first meets the types (the same scene, the same colours)
std::vector<std::string> module_colors(const Scene& scene) {
  static const char* const kOwn[] = {"#2a9d8f", "#b5179e", "#e9c46a", "#4361ee", "#6a994e",
                                     "#f28482", "#7b2cbf", "#00b4d8", "#bc6c25", "#3a5a40"};
  std::map<std::string, std::string> own;
  std::vector<std::string> out;
  for (const SceneModule& m : scene.modules) {
    if (const char* c = module_color(m.type)) {
      out.push_back(c);
      continue;
    }
    if (!own.count(m.type)) own[m.type] = kOwn[own.size() % (sizeof kOwn / sizeof kOwn[0])];
    out.push_back(own[m.type]);
  }
  return out;
}

nlohmann::json scene_json(const Scene& scene, const ChainModel& chain) {
  if (chain.size() != static_cast<int>(scene.modules.size()))
    throw std::invalid_argument("scene_json: the chain model has " + std::to_string(chain.size()) +
                                " modules, the scene " + std::to_string(scene.modules.size()));
  nlohmann::json modules = nlohmann::json::array();
  const std::vector<std::string> colors = module_colors(scene);
  for (size_t i = 0; i < scene.modules.size(); ++i) {
    const ModuleDef& def = chain.modules[i];
    nlohmann::json bodies = nlohmann::json::array();
    for (const BodyDef& b : def.bodies) {
      nlohmann::json j = {{"name", b.name}, {"shape", shape_name(b.shape)}, {"mass_kg", b.mass_kg}};
      if (b.shape == Shape::Box)
        j["box_m"] = {b.box_m.x(), b.box_m.y(), b.box_m.z()};
      else
        j["radius_m"] = b.radius_m;
      if (b.shape == Shape::Capsule || b.shape == Shape::Cylinder) j["length_m"] = b.length_m;
      // the module's up (its frame's z) in the body's frame: how a viewer tells a chain's roll
      const Eigen::Vector3d up = b.pose.orientation.conjugate() * Eigen::Vector3d::UnitZ();
      j["up"] = {std::round(up.x() * 1e9) / 1e9, std::round(up.y() * 1e9) / 1e9, std::round(up.z() * 1e9) / 1e9};
      bodies.push_back(j);
    }
    nlohmann::json servos = nlohmann::json::array();
    for (int a : driven_servo_actuators(def)) servos.push_back(def.actuators[a].name);
    modules.push_back({{"index", i},
                       {"type", scene.modules[i].type},
                       {"firmware", scene.modules[i].firmware},
                       {"color", colors[i]},
                       {"bodies", bodies},
                       {"servos", servos}});
  }
  return {{"scene", scene.name},
          {"source", scene.source},
          {"seed", scene.world.seed},
          {"duration_s", scene.duration_s},
          {"dt_us", scene.world.dt_us},
          {"tick_us", scene.tick_us},
          {"trace_hz", scene.trace_hz},
          {"conventions",
           "SI units; z up; trace quaternions are qw,qx,qy,qz (world frame); capsule and cylinder axes are the "
           "body's local z; a capsule's length_m is its straight part"},
          {"environment", environment_json(scene.world)},  // format: environment_json.cpp
          {"modules", modules},
          {"central", {{"index", scene.modules.size()}, {"firmware", scene.central.firmware}}}};
}

nlohmann::json write_scene_json(RunOutput* out, const Scene& scene, const ChainModel& chain) {
  nlohmann::json j = scene_json(scene, chain);
  out->write_json("scene.json", j);
  return j;
}

}  // namespace chainsim
