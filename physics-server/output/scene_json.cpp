#include "output/scene_json.h"

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
  return "#cccccc";
}

nlohmann::json scene_json(const Scene& scene) {
  nlohmann::json modules = nlohmann::json::array();
  for (size_t i = 0; i < scene.modules.size(); ++i) {
    const ModuleDef def = find_module_def(scene.world.module_types, scene.modules[i].type);
    nlohmann::json bodies = nlohmann::json::array();
    for (const BodyDef& b : def.bodies) {
      nlohmann::json j = {{"name", b.name}, {"shape", shape_name(b.shape)}, {"mass_kg", b.mass_kg}};
      if (b.shape == Shape::Box)
        j["box_m"] = {b.box_m.x(), b.box_m.y(), b.box_m.z()};
      else
        j["radius_m"] = b.radius_m;
      if (b.shape == Shape::Capsule || b.shape == Shape::Cylinder) j["length_m"] = b.length_m;
      bodies.push_back(j);
    }
    nlohmann::json servos = nlohmann::json::array();
    for (int a : driven_servo_actuators(def)) servos.push_back(def.actuators[a].name);
    modules.push_back({{"index", i},
                       {"type", scene.modules[i].type},
                       {"firmware", scene.modules[i].firmware},
                       {"color", module_color(scene.modules[i].type)},
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

nlohmann::json write_scene_json(RunOutput* out, const Scene& scene) {
  nlohmann::json j = scene_json(scene);
  out->write_json("scene.json", j);
  return j;
}

}  // namespace chainsim
