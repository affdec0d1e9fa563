// A Scene as a scene file. See scene_write.h.
#include "scene/scene_write.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "scene/scene_edit.h"
#include "scene/scene_stop.h"
#include "text/number_text.h"

namespace chainsim {

namespace {

YAML::Node yaml_number(double v) { return YAML::Node(round_trip_text(v)); }

YAML::Node yaml_vector3(const Eigen::Vector3d& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (int i = 0; i < 3; ++i) n.push_back(yaml_number(v[i]));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

// a file as loading resolved it (relative to the working directory, or
// absolute), made absolute: the same file from any directory
std::string absolute_path_text(const std::string& file) {
  return std::filesystem::absolute(file).lexically_normal().string();
}

// a program given as a path (it has a '/') is a file; a bare name stays a name
std::string program_path_text(const std::string& program) {
  return program.find('/') != std::string::npos ? absolute_path_text(program) : program;
}

YAML::Node yaml_material(const Material& m) {
  YAML::Node n;
  n["mu"] = yaml_number(m.mu);
  n["bounce"] = yaml_number(m.bounce);
  n["soft_erp"] = yaml_number(m.soft_erp);
  n["soft_cfm"] = yaml_number(m.soft_cfm);
  return n;
}

YAML::Node yaml_params(const std::map<std::string, int32_t>& ps) {
  YAML::Node n(YAML::NodeType::Map);
  for (const auto& [k, v] : ps) n[k] = v;
  return n;
}

YAML::Node yaml_segment(const PipeSegment& g) {
  YAML::Node n;
  switch (g.type) {
    case PipeSegment::Type::Straight:
      n["type"] = "straight";
      n["length_m"] = yaml_number(g.length_m);
      if (!std::isnan(g.slope_deg)) n["slope_deg"] = yaml_number(g.slope_deg);
      break;
    case PipeSegment::Type::Elbow:
    case PipeSegment::Type::Split:
      n["type"] = g.type == PipeSegment::Type::Elbow ? "elbow" : "split";
      n["bend_radius_m"] = yaml_number(g.bend_radius_m);
      n["angle_deg"] = yaml_number(g.angle_deg);
      n["direction_deg"] = yaml_number(g.direction_deg);
      break;
    case PipeSegment::Type::Tee:
      n["type"] = "tee";
      n["run_length_m"] = yaml_number(g.run_length_m);
      n["branch_length_m"] = yaml_number(g.branch_length_m);
      n["direction_deg"] = yaml_number(g.direction_deg);
      n["follow"] = g.follow_branch ? "branch" : "run";
      break;
  }
  return n;
}

YAML::Node yaml_environment(const EnvironmentConfig& env, const Material& ground) {
  YAML::Node e;
  e["type"] = environment_type_name(env.type);
  e["material"] = yaml_material(ground);
  if (env.type != EnvironmentType::Plane) e["ground_plane"] = env.ground_plane;  // a plane always has it
  e["ground_surface"] = env.ground_surface;
  if (env.type == EnvironmentType::Pipe) {
    const PipeSpec& p = env.pipe;
    YAML::Node n;
    n["inner_diameter_m"] = yaml_number(p.inner_diameter_m);
    n["collider"] = p.collider == PipeCollider::Mesh ? "mesh" : "analytic";
    n["entry_m"] = yaml_vector3(p.entry_m);
    n["heading_deg"] = yaml_number(p.heading_deg);
    n["slope_deg"] = yaml_number(p.slope_deg);
    n["mesh_segments"] = p.mesh_segments;
    n["surface"] = p.surface;
    for (const PipeSegment& g : p.segments) n["segments"].push_back(yaml_segment(g));
    e["pipe"] = n;
  } else if (env.type == EnvironmentType::Terrain) {
    const TerrainSpec& t = env.terrain;
    YAML::Node n;
    n["amplitude_m"] = yaml_number(t.amplitude_m);
    n["wavelength_m"] = yaml_number(t.wavelength_m);
    n["width_m"] = yaml_number(t.width_m);
    n["length_m"] = yaml_number(t.length_m);
    n["resolution_m"] = yaml_number(t.resolution_m);
    n["walls"] = t.walls;
    n["wall_height_m"] = yaml_number(t.wall_height_m);
    n["wall_thickness_m"] = yaml_number(t.wall_thickness_m);
    n["surface"] = t.surface;
    n["wall_surface"] = t.wall_surface;
    e["terrain"] = n;
  } else if (env.type == EnvironmentType::Mesh) {
    const MeshSpec& m = env.mesh;
    YAML::Node n;
    n["file"] = absolute_path_text(m.file);
    n["scale"] = yaml_number(m.scale);
    n["position_m"] = yaml_vector3(m.position_m);
    n["rpy_deg"] = yaml_vector3(m.rpy_deg);
    n["surface"] = m.surface;
    e["mesh"] = n;
  }
  return e;
}

YAML::Node yaml_program(const SceneProgram& p) {
  YAML::Node n(YAML::NodeType::Map);
  if (!p.firmware.empty()) n["firmware"] = program_path_text(p.firmware);
  if (!p.params.empty()) n["params"] = yaml_params(p.params);
  if (p.may_stay_silent) n["may_stay_silent"] = *p.may_stay_silent;
  if (p.target) n["target"] = target_name(*p.target);
  return n;
}

// a module of the chain: what differs from what its type gets from
// `programs` (scene_module_of_type); empty when nothing does
YAML::Node module_overrides(const Scene& s, const SceneModule& m) {
  const SceneModule from = scene_module_of_type(s, m.type);
  YAML::Node n(YAML::NodeType::Map);
  if (m.firmware != from.firmware) n["firmware"] = program_path_text(m.firmware);
  std::map<std::string, int32_t> own;
  for (const auto& [k, v] : m.params) {
    const auto it = from.params.find(k);
    if (it == from.params.end() || it->second != v) own[k] = v;
  }
  if (!own.empty()) n["params"] = yaml_params(own);
  if (m.may_stay_silent != from.may_stay_silent) n["may_stay_silent"] = m.may_stay_silent;
  if (m.target != from.target) n["target"] = target_name(m.target);
  return n;
}

// the letter of a module type, or 0
char letter_of_type(const std::string& type) {
  for (char l : std::string("TRHSEWP"))
    if (module_type_for_letter(l) == type) return l;
  return 0;
}

YAML::Node yaml_chain(const Scene& s) {
  // letters when every module is its type's as `programs` gives it
  std::string letters;
  for (const SceneModule& m : s.modules) {
    const char l = letter_of_type(m.type);
    if (l == 0 || module_overrides(s, m).size() != 0) {
      letters.clear();
      break;
    }
    letters += l;
  }
  if (!letters.empty()) return YAML::Node(letters);
  YAML::Node list(YAML::NodeType::Sequence);
  for (const SceneModule& m : s.modules) {
    YAML::Node n;
    n["type"] = m.type;
    for (const auto& kv : module_overrides(s, m)) n[kv.first] = kv.second;
    list.push_back(n);
  }
  return list;
}

YAML::Node yaml_placement(const ScenePlacement& p) {
  YAML::Node n;
  if (p.at_pipe_entry) {
    n["at"] = "pipe_entry";
    n["inset_m"] = yaml_number(p.inset_m);
  } else {
    n["position_m"] = yaml_vector3(p.position_m);
    n["heading_deg"] = yaml_number(p.heading_deg);
  }
  n["roll_deg"] = yaml_number(p.roll_deg);
  return n;
}

YAML::Node yaml_central(const Scene& s) {
  const SceneModule& c = s.central;
  YAML::Node n;
  n["program"] = program_path_text(c.firmware);
  n["params"] = yaml_params(c.params);
  n["discovery_s"] = yaml_number(s.discovery_s);
  if (c.target != s.target.value_or(Target::Native)) n["target"] = target_name(c.target);
  return n;
}

}  // namespace

std::string write_scene(const Scene& s) {
  YAML::Node root;
  root["name"] = s.name;
  root["duration_s"] = yaml_number(s.duration_s);
  root["seed"] = s.world.seed;
  YAML::Node physics;
  physics["dt_us"] = s.world.dt_us;
  physics["tick_us"] = s.tick_us;
  physics["gravity_m_s2"] = yaml_number(s.world.gravity_m_s2);
  if (s.world.solver == WorldConfig::Solver::Exact) {
    physics["solver"] = "exact";  // iterations are QuickStep's only
  } else {
    physics["solver"] = "quickstep";
    physics["solver_iterations"] = s.world.solver_iterations;
  }
  if (s.world.dock) {
    YAML::Node dock;
    dock["play_deg"] = yaml_number(s.world.dock->play_deg);
    if (s.world.dock->stiffness_nm_per_rad > 0) {
      dock["stiffness_n_m_per_rad"] = yaml_number(s.world.dock->stiffness_nm_per_rad);
      dock["damping_n_m_s_per_rad"] = yaml_number(s.world.dock->damping_nm_s_per_rad);
    }
    physics["dock"] = dock;
  }
  root["physics"] = physics;
  // a scene without `environment` has a plane whose ground_plane is false
  // (it has the plane all the same); any `environment` makes it true
  const EnvironmentConfig& env = s.world.environment;
  if (env.type != EnvironmentType::Plane || env.ground_plane)
    root["environment"] = yaml_environment(env, s.world.ground);
  if (!s.world.environment.contacts.empty()) {
    YAML::Node list(YAML::NodeType::Sequence);
    for (const MaterialPair& p : s.world.environment.contacts) {
      YAML::Node n = yaml_material(p.material);
      YAML::Node between(YAML::NodeType::Sequence);
      between.push_back(p.a);
      between.push_back(p.b);
      between.SetStyle(YAML::EmitterStyle::Flow);
      YAML::Node entry;
      entry["between"] = between;
      for (const auto& kv : n) entry[kv.first] = kv.second;
      list.push_back(entry);
    }
    root["contacts"] = list;
  }
  if (!s.module_type_files.empty())
    for (const auto& [name, file] : s.module_type_files) root["module_types"][name] = absolute_path_text(file);
  if (!s.programs.empty())
    for (const auto& [type, p] : s.programs) root["programs"][type] = yaml_program(p);
  if (s.target) root["target"] = target_name(*s.target);
  root["chain"] = yaml_chain(s);
  root["placement"] = yaml_placement(s.placement);
  root["central"] = yaml_central(s);
  root["pic"]["cpu_budget_us"] = s.pic.cpu_budget_us;
  root["pic"]["stall_ms"] = s.pic.stall_ms;
  if (!s.stop_when.empty())
    for (const StopRule& r : s.stop_when) root["stop_when"].push_back(stop_rule_yaml(r));
  root["output"]["trace_hz"] = yaml_number(s.trace_hz);
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace chainsim
