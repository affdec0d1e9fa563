#include "scene/scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "physics/units.h"
#include "scene/scene_environment.h"
#include "scene/scene_modules.h"
#include "scene/scene_yaml.h"

namespace chainsim {
namespace {

using Ctx = SceneYaml;

std::map<std::string, int32_t> get_params(const Ctx& c, const YAML::Node& map,
                                          const std::string& path) {
  std::map<std::string, int32_t> out;
  const YAML::Node n = map["params"];
  if (!n) return out;
  if (!n.IsMap()) c.fail(n, "'" + path + ".params' must be a mapping of name: integer");
  for (const auto& kv : n) {
    const std::string name = kv.first.as<std::string>();
    if (name.empty() || name.size() > 15)
      c.fail(kv.first, "parameter name '" + name + "' must have 1 to 15 characters");
    out[name] = static_cast<int32_t>(
        c.integer(n, name, 0, INT32_MIN, INT32_MAX, path + ".params"));
  }
  if (out.size() > 16) c.fail(n, "'" + path + ".params' has more than 16 parameters");
  return out;
}

void load_chain(const Ctx& c, const YAML::Node& root, Scene* s) {
  const YAML::Node n = root["chain"];
  if (!n) c.fail(root, "missing key 'chain' (a string such as \"RRRRRRRR\" or a list of modules)");
  if (n.IsScalar()) {
    const std::string letters = n.as<std::string>();
    if (letters.empty()) c.fail(n, "'chain' is empty");
    for (char l : letters) {
      const std::string type = module_type_for_letter(l);
      if (type.empty())
        c.fail(n, std::string("'chain' has unknown module letter '") + l +
                       "' (T touch, R rotation, H helicoidal, S support, E extension, "
                       "W traveller, P passive)");
      s->modules.push_back({type, default_firmware(type), {}});
    }
  } else if (n.IsSequence()) {
    for (size_t i = 0; i < n.size(); ++i) {
      const YAML::Node m = n[i];
      const std::string p = "chain[" + std::to_string(i) + "]";
      c.keys(m, p, {"type", "firmware", "params"});
      if (!m["type"]) c.fail(m, "'" + p + "' needs a 'type'");
      SceneModule sm;
      sm.type = c.string(m, "type", "", p);
      sm.firmware = c.string(m, "firmware", default_firmware(sm.type), p);
      sm.params = get_params(c, m, p);
      s->modules.push_back(sm);
    }
    if (s->modules.empty()) c.fail(n, "'chain' is empty");
  } else {
    c.fail(n, "'chain' must be a string of module letters or a list of modules");
  }
  if (s->modules.size() > 64) c.fail(n, "'chain' has more than 64 modules");
}

}  // namespace

std::vector<std::string> Scene::chain_types() const {
  std::vector<std::string> types;
  for (const SceneModule& m : modules) types.push_back(m.type);
  return types;
}

std::string module_type_for_letter(char letter) {
  switch (letter) {
    case 'T': return "touch";
    case 'R': return "rotation";
    case 'H': return "helicoidal";
    case 'S': return "support";
    case 'E': return "extension";
    case 'W': return "traveller";
    case 'P': return "passive";
    default: return "";
  }
}

std::string default_firmware(const std::string& type) { return "fw-" + type; }

Scene load_scene_text(const std::string& text, const std::string& name) {
  const Ctx c{name};
  const YAML::Node root = c.parse(text);
  if (!root || !root.IsMap()) throw SceneError(name + ": a scene must be a YAML mapping");
  c.keys(root, "scene",
             {"name", "duration_s", "seed", "physics", "environment", "contacts", "module_types",
              "chain", "placement", "central", "output"});

  Scene s;
  s.source = name;
  s.name = c.string(root, "name", "unnamed", "scene");
  s.duration_s = c.number(root, "duration_s", s.duration_s, 0.001, 86400.0, "scene");
  s.world.seed = static_cast<uint64_t>(c.integer(root, "seed", 1, 0, INT64_MAX, "scene"));

  if (const YAML::Node p = root["physics"]) {
    c.keys(p, "physics", {"dt_us", "tick_us", "gravity_m_s2", "solver_iterations"});
    s.world.dt_us = c.integer(p, "dt_us", s.world.dt_us, 10, 100000, "physics");
    s.tick_us = c.integer(p, "tick_us", s.tick_us, 10, 1000000, "physics");
    s.world.gravity_m_s2 = c.number(p, "gravity_m_s2", s.world.gravity_m_s2, 0.0, 100.0, "physics");
    s.world.solver_iterations =
        static_cast<int>(c.integer(p, "solver_iterations", s.world.solver_iterations, 1, 10000, "physics"));
    if (s.tick_us % s.world.dt_us != 0)
      c.fail(p, "'physics.tick_us' (" + std::to_string(s.tick_us) +
                     ") must be a multiple of 'physics.dt_us' (" + std::to_string(s.world.dt_us) + ")");
  }

  // environment and contacts: scene_environment.cpp; mesh files relative to the scene's directory
  const std::string base_dir =
      name.empty() || name[0] == '<' ? "" : std::filesystem::path(name).parent_path().string();
  load_scene_environment(name, base_dir, root["environment"], root["contacts"], &s.world);

  load_scene_module_types(name, base_dir, root["module_types"], &s.world);  // scene_modules.cpp
  load_chain(c, root, &s);
  check_scene_chain_types(name, root["chain"], s);

  if (const YAML::Node p = root["placement"]) {
    c.keys(p, "placement", {"position_m", "heading_deg", "at", "inset_m"});
    s.world.head_position = c.vec3(p, "position_m", s.world.head_position, "placement");
    s.world.heading_rad = deg_to_rad(c.number(p, "heading_deg", 0.0, -360.0, 360.0, "placement"));
    load_scene_placement_at(name, p, s.chain_types(), &s.world);  // at: pipe_entry
  }

  s.central = {"central", "fw-central", {}};
  if (const YAML::Node ce = root["central"]) {
    c.keys(ce, "central", {"program", "params"});
    s.central.firmware = c.string(ce, "program", "fw-central", "central");
    s.central.params = get_params(c, ce, "central");
  }

  if (const YAML::Node o = root["output"]) {
    c.keys(o, "output", {"trace_hz"});
    s.trace_hz = c.number(o, "trace_hz", s.trace_hz, 0.001, 1e6, "output");
  }
  return s;
}

Scene load_scene_file(const std::string& path) {
  return load_scene_text(SceneYaml{path}.read_file("scene file"), path);
}

Scene default_scene() { return load_scene_text(default_scene_text(), "<built-in default scene>"); }

}  // namespace chainsim
