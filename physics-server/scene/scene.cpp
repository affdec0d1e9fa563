#include "scene/scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "model/units.h"
#include "readers/safe_text.h"
#include "scene/scene_edit.h"
#include "scene/scene_environment.h"
#include "scene/scene_stop.h"
#include "scene/scene_modules.h"
#include "scene/scene_yaml.h"

namespace chainsim {
namespace {

using Ctx = SceneYaml;

// map's `params` into *params, and where each key is into *at
void get_params(const Ctx& c, const YAML::Node& map, const std::string& path,
                std::map<std::string, int32_t>* params, std::map<std::string, std::string>* at) {
  const YAML::Node n = map["params"];
  if (!n) return;
  if (!n.IsMap()) c.fail(n, "'" + path + ".params' must be a mapping of name: integer");
  for (const auto& kv : n) {
    const std::string name = kv.first.as<std::string>();
    if (!is_param_name(name))
      c.fail(kv.first, "parameter name '" + name + "' must be 1 to 15 letters, digits or '_'");
    (*params)[name] = static_cast<int32_t>(
        c.integer(n, name, 0, INT32_MIN, INT32_MAX, path + ".params"));
    (*at)[name] = c.where(kv.first);
  }
  if (params->size() > 16) c.fail(n, "'" + path + ".params' has more than 16 parameters");
}

Target load_target(const Ctx& c, const YAML::Node& n, const std::string& path) {
  return c.choice(n, "target", "native", {"native", "pic"}, path) == "pic" ? Target::Pic : Target::Native;
}

// a program given as a relative path resolves against the scene's directory,
// as mesh and module-type files do (a bare name is looked up at run time)
void resolve_program(const std::string& base_dir, std::string* program) {
  if (base_dir.empty()) return;
  const std::filesystem::path given(*program);
  if (program->find('/') != std::string::npos && given.is_relative())
    *program = (std::filesystem::path(base_dir) / given).string();
}

// `programs: {all: {firmware, params}, <type>: {firmware, params}}`: the
// program and parameters of every module, and of every module of a type. A
// module's own firmware wins over its type's, which wins over all's; params
// merge name by name in the same order (scene_module_of_type).
std::map<std::string, SceneProgram> load_programs(const Ctx& c, const YAML::Node& n, const Scene& s,
                                                  const std::string& base_dir) {
  std::map<std::string, SceneProgram> out;
  if (!n) return out;
  if (!n.IsMap()) c.fail(n, "'programs' must be a mapping of module type (or all): {firmware, params}");
  for (const auto& kv : n) {
    const std::string type = kv.first.as<std::string>();
    const std::string p = "programs." + type;
    if (type != "all" && !is_module_type(s.world, type))
      c.fail(kv.first, "'programs' names module type '" + type + "', which is not known (the built-in types, "
                       "the scene's module_types, or all)");
    if (!kv.second.IsMap()) c.fail(kv.second, "'" + p + "' must be a mapping with firmware and/or params");
    c.keys(kv.second, p, {"firmware", "params", "may_stay_silent", "target"});
    SceneProgram d;
    if (kv.second["target"]) {
      d.target = load_target(c, kv.second, p);
      d.target_at = c.where(kv.second["target"]);
    }
    if (kv.second["may_stay_silent"]) d.may_stay_silent = c.flag(kv.second, "may_stay_silent", false, p);
    d.firmware = c.string(kv.second, "firmware", "", p);
    resolve_program(base_dir, &d.firmware);
    if (kv.second["firmware"]) d.firmware_at = c.where(kv.second["firmware"]);
    get_params(c, kv.second, p, &d.params, &d.param_at);
    out[type] = d;
  }
  return out;
}

// chain: the scene's chain node (a module's own may_stay_silent wins when given)
void apply_programs(const YAML::Node& chain, Scene* s) {
  for (size_t i = 0; i < s->modules.size(); ++i) {
    SceneModule& m = s->modules[i];
    const SceneModule from = scene_module_of_type(*s, m.type);
    if (m.firmware.empty()) {
      m.firmware = from.firmware;
      if (!from.firmware_at.empty()) m.firmware_at = from.firmware_at;
    }
    std::map<std::string, int32_t> params = from.params;
    std::map<std::string, std::string> at = from.param_at;
    for (const auto& [k, v] : m.params) params[k] = v;
    for (const auto& [k, v] : m.param_at) at[k] = v;
    m.params = params;
    m.param_at = at;
    if (!(chain.IsSequence() && chain[i]["may_stay_silent"])) m.may_stay_silent = from.may_stay_silent;
    if (m.target_at.empty()) {  // the module's own target wins, then its type's, then all's, then the scene's
      m.target = from.target;
      m.target_at = from.target_at;
    }
  }
}

void load_chain(const Ctx& c, const YAML::Node& root, const std::string& base_dir, Scene* s) {
  const YAML::Node n = root["chain"];
  if (!n) c.fail(root, "missing key 'chain' (a string such as \"RRRRRRRR\" or a list of modules)");
  // bounded before anything is built: one process and one socket per module
  const size_t count = n.IsScalar() ? n.Scalar().size() : n.IsSequence() ? n.size() : 0;
  if (count > kMaxSceneModules)
    c.fail(n, "'chain' has " + std::to_string(count) + " modules, more than the limit of " +
                  std::to_string(kMaxSceneModules));
  if (n.IsScalar()) {
    const std::string letters = n.as<std::string>();
    if (letters.empty()) c.fail(n, "'chain' is empty");
    for (char l : letters) {
      const std::string type = module_type_for_letter(l);
      if (type.empty())
        c.fail(n, std::string("'chain' has unknown module letter '") + l +
                       "' (T touch, R rotation, H helicoidal, S support, E extension, "
                       "W traveller, P passive)");
      SceneModule sm;
      sm.type = type;  // the program: apply_programs
      sm.firmware_at = c.where(n);
      s->modules.push_back(sm);
    }
  } else if (n.IsSequence()) {
    for (size_t i = 0; i < n.size(); ++i) {
      const YAML::Node m = n[i];
      const std::string p = "chain[" + std::to_string(i) + "]";
      c.keys(m, p, {"type", "firmware", "params", "may_stay_silent", "target"});
      if (!m["type"]) c.fail(m, "'" + p + "' needs a 'type'");
      SceneModule sm;
      if (m["target"]) {
        sm.target = load_target(c, m, p);
        sm.target_at = c.where(m["target"]);
      }
      sm.type = c.string(m, "type", "", p);
      sm.firmware = c.string(m, "firmware", "", p);  // empty: apply_programs
      resolve_program(base_dir, &sm.firmware);
      sm.firmware_at = c.where(m["firmware"] ? m["firmware"] : m);
      get_params(c, m, p, &sm.params, &sm.param_at);
      sm.may_stay_silent = c.flag(m, "may_stay_silent", false, p);
      s->modules.push_back(sm);
    }
    if (s->modules.empty()) c.fail(n, "'chain' is empty");
  } else {
    c.fail(n, "'chain' must be a string of module letters or a list of modules");
  }
}

// a run is whole ticks: a tick longer than the run would silently stretch it
void check_tick_within_duration(const Ctx& c, const YAML::Node& root, const Scene& s) {
  if (s.tick_us <= std::llround(s.duration_s * 1e6)) return;
  const YAML::Node p = root["physics"];
  const YAML::Node at = p && p["tick_us"] ? p["tick_us"] : root;  // the default tick fits the shortest run
  char duration[32];
  std::snprintf(duration, sizeof duration, "%g", s.duration_s);
  c.fail(at, "'physics.tick_us' (" + std::to_string(s.tick_us) + " us) is longer than the run ('duration_s' " +
                 duration + " s)");
}

}  // namespace

std::vector<std::string> Scene::chain_types() const {
  std::vector<std::string> types;
  for (const SceneModule& m : modules) types.push_back(m.type);
  return types;
}

ChainModel compile_chain(const Scene& scene) { return compile_chain(scene.world, scene.chain_types()); }

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

SceneError::SceneError(const std::string& message) : std::runtime_error(shown_text(message)) {}

std::string default_firmware(const std::string& type) { return "fw-" + type; }

const char* target_name(Target t) { return t == Target::Pic ? "pic" : "native"; }

void set_target(Scene* scene, Target t) {
  for (SceneModule& m : scene->modules) m.target = t;
  scene->central.target = t;
  scene->target = t;
  for (auto& [type, program] : scene->programs) {
    program.target.reset();
    program.target_at.clear();
  }
}

bool uses_pic(const Scene& scene) {
  for (const SceneModule& m : scene.modules)
    if (m.target == Target::Pic) return true;
  return scene.central.target == Target::Pic;
}

Scene load_scene_text(const std::string& text, const std::string& name) {
  const Ctx c{name};
  const YAML::Node root = c.parse(text);
  if (!root || !root.IsMap()) throw SceneError(name + ": a scene must be a YAML mapping");
  c.keys(root, "scene",
             {"name", "duration_s", "seed", "physics", "environment", "contacts", "module_types",
              "programs", "chain", "placement", "central", "output", "target", "pic", "stop_when"});

  Scene s;
  s.source = name;
  s.name = c.name(root, "name", "unnamed", "scene");  // names the run directory: runs/<name>-<date>
  s.duration_s = c.number(root, "duration_s", s.duration_s, 0.001, 86400.0, "scene");
  s.world.seed = static_cast<uint64_t>(c.integer(root, "seed", 1, 0, INT64_MAX, "scene"));

  if (const YAML::Node p = root["physics"]) {
    c.keys(p, "physics", {"dt_us", "tick_us", "gravity_m_s2", "solver", "solver_iterations", "dock"});
    s.world.dt_us = c.integer(p, "dt_us", s.world.dt_us, 10, 100000, "physics");
    s.tick_us = c.integer(p, "tick_us", s.tick_us, 10, 1000000, "physics");
    s.world.gravity_m_s2 = c.number(p, "gravity_m_s2", s.world.gravity_m_s2, 0.0, 100.0, "physics");
    s.world.solver_iterations =
        static_cast<int>(c.integer(p, "solver_iterations", s.world.solver_iterations, 1, 10000, "physics"));
    if (c.choice(p, "solver", "quickstep", {"quickstep", "exact"}, "physics") == "exact") {
      if (p["solver_iterations"])
        c.fail(p["solver_iterations"], "'physics.solver_iterations' applies to the quickstep solver only, and "
                                       "'physics.solver' is exact");
      s.world.solver = WorldConfig::Solver::Exact;
    }
    if (const YAML::Node d = p["dock"]) {  // docks as measured joints (world.h, WorldConfig::dock)
      if (!d.IsMap()) c.fail(d, "'physics.dock' must be a mapping (play_deg, stiffness_n_m_per_rad, damping_n_m_s_per_rad)");
      c.keys(d, "physics.dock", {"play_deg", "stiffness_n_m_per_rad", "damping_n_m_s_per_rad"});
      WorldConfig::DockConfig dc;
      dc.play_deg = c.number(d, "play_deg", 0.0, 0.0, 10.0, "physics.dock");
      dc.stiffness_nm_per_rad = c.number(d, "stiffness_n_m_per_rad", 0.0, 0.0, 1e6, "physics.dock");
      dc.damping_nm_s_per_rad = c.number(d, "damping_n_m_s_per_rad", 0.0, 0.0, 1e3, "physics.dock");
      if (d["damping_n_m_s_per_rad"] && dc.stiffness_nm_per_rad == 0)
        c.fail(d["damping_n_m_s_per_rad"], "'physics.dock.damping_n_m_s_per_rad' needs a 'stiffness_n_m_per_rad' "
                                          "above 0 (without one the dock is as stiff as the solver makes a joint)");
      s.world.dock = dc;
    }
    if (s.tick_us % s.world.dt_us != 0)
      c.fail(p, "'physics.tick_us' (" + std::to_string(s.tick_us) +
                     ") must be a multiple of 'physics.dt_us' (" + std::to_string(s.world.dt_us) + ")");
  }
  check_tick_within_duration(c, root, s);

  // environment and contacts: scene_environment.cpp; mesh files relative to the scene's directory
  const std::string base_dir =
      name.empty() || name[0] == '<' ? "" : std::filesystem::path(name).parent_path().string();
  load_scene_environment(name, base_dir, root["environment"], root["contacts"], &s.world);

  load_scene_module_types(name, base_dir, root["module_types"], &s);  // scene_modules.cpp
  load_chain(c, root, base_dir, &s);
  check_scene_chain_types(name, root["chain"], s);
  // `target`: every endpoint's, unless programs or the module say otherwise
  if (root["target"]) {
    s.target = load_target(c, root, "scene");
    s.target_at = c.where(root["target"]);
  }
  s.programs = load_programs(c, root["programs"], s, base_dir);
  apply_programs(root["chain"], &s);
  if (const YAML::Node p = root["pic"]) {
    c.keys(p, "pic", {"cpu_budget_us", "stall_ms"});
    s.pic.cpu_budget_us = c.integer(p, "cpu_budget_us", 0, 0, 1000000000, "pic");
    s.pic.stall_ms = c.integer(p, "stall_ms", s.pic.stall_ms, 1, 3600000, "pic");
  }

  if (const YAML::Node p = root["placement"]) {
    c.keys(p, "placement", {"position_m", "heading_deg", "roll_deg", "at", "inset_m"});
    ScenePlacement& pl = s.placement;
    pl.position_m = c.vec3(p, "position_m", pl.position_m, "placement");
    pl.heading_deg = c.number(p, "heading_deg", 0.0, -360.0, 360.0, "placement");
    pl.roll_deg = c.number(p, "roll_deg", 0.0, -360.0, 360.0, "placement");
    s.world.head_position = pl.position_m;
    s.world.heading_rad = deg_to_rad(pl.heading_deg);
    s.world.roll_rad = deg_to_rad(pl.roll_deg);
    load_scene_placement_at(name, p, s.chain_types(), &s.world, &pl);  // at: pipe_entry
  }
  load_scene_stop_when(name, root["stop_when"], &s);  // scene_stop.cpp

  s.central.type = "central";
  s.central.firmware = "fw-central";
  s.central.firmware_at = c.where(root);
  if (s.target) {
    s.central.target = *s.target;
    s.central.target_at = s.target_at;
  }
  if (const YAML::Node ce = root["central"]) {
    c.keys(ce, "central", {"program", "params", "discovery_s", "target"});
    if (ce["target"]) {
      s.central.target = load_target(c, ce, "central");
      s.central.target_at = c.where(ce["target"]);
    }
    s.discovery_s = c.number(ce, "discovery_s", s.discovery_s, 0.001, 86400.0, "central");
    s.central.firmware = c.string(ce, "program", "fw-central", "central");
    resolve_program(base_dir, &s.central.firmware);
    s.central.firmware_at = c.where(ce["program"] ? ce["program"] : ce);
    get_params(c, ce, "central", &s.central.params, &s.central.param_at);
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
