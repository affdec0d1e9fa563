// Environment keys of a scene. See scene_environment.h and docs/scene-reference.md.
#include "scene/scene_environment.h"

#include "scene/scene_yaml.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "environment/mesh_loader.h"
#include "environment/pipe_path.h"
#include "physics/placement.h"
#include "environment/terrain.h"
#include "model/units.h"

namespace chainsim {
namespace {

PipeSegment load_segment(const SceneYaml& y, const YAML::Node& n, const std::string& p, double diameter) {
  PipeSegment g;
  if (!n.IsMap()) y.fail(n, "'" + p + "' must be a mapping such as {type: straight, length_m: 0.5}");
  if (!n["type"]) y.fail(n, "'" + p + "' needs a 'type' (straight, elbow, tee or split)");
  const std::string type = y.choice(n, "type", "", {"straight", "elbow", "tee", "split"}, p);
  if (type == "straight") {
    y.keys(n, p, {"type", "length_m", "slope_deg"});
    if (!n["length_m"]) y.fail(n, "'" + p + "' (straight) needs 'length_m'");
    g.type = PipeSegment::Type::Straight;
    g.length_m = y.positive(n, "length_m", 0, 1000, p);
    if (n["slope_deg"]) g.slope_deg = y.number(n, "slope_deg", 0, -90, 90, p);
  } else if (type == "elbow" || type == "split") {
    y.keys(n, p, {"type", "bend_radius_m", "angle_deg", "direction_deg"});
    if (!n["bend_radius_m"]) y.fail(n, "'" + p + "' (" + type + ") needs 'bend_radius_m'");
    g.type = type == "elbow" ? PipeSegment::Type::Elbow : PipeSegment::Type::Split;
    g.bend_radius_m = y.positive(n, "bend_radius_m", 0, 1000, p);
    g.angle_deg = y.number(n, "angle_deg", 90, 0, 180, p, true);
    g.direction_deg = y.number(n, "direction_deg", 0, -360, 360, p);
  } else {
    y.keys(n, p, {"type", "run_length_m", "branch_length_m", "direction_deg", "follow"});
    g.type = PipeSegment::Type::Tee;
    g.run_length_m = y.positive(n, "run_length_m", 3 * diameter, 1000, p);
    g.branch_length_m = y.positive(n, "branch_length_m", 2 * diameter, 1000, p);
    g.direction_deg = y.number(n, "direction_deg", 0, -360, 360, p);
    g.follow_branch = y.choice(n, "follow", "run", {"run", "branch"}, p) == "branch";
  }
  return g;
}

void load_pipe(const SceneYaml& y, const YAML::Node& n, PipeSpec* pipe) {
  const std::string p = "environment.pipe";
  y.keys(n, p, {"inner_diameter_m", "collider", "entry_m", "heading_deg", "slope_deg", "segments",
                "mesh_segments", "surface"});
  pipe->inner_diameter_m = y.positive(n, "inner_diameter_m", pipe->inner_diameter_m, 10.0, p);
  pipe->collider = y.choice(n, "collider", "analytic", {"analytic", "mesh"}, p) == "mesh"
                       ? PipeCollider::Mesh
                       : PipeCollider::Analytic;
  pipe->entry_m = y.vec3(n, "entry_m", pipe->entry_m, p);
  pipe->heading_deg = y.number(n, "heading_deg", 0, -360, 360, p);
  pipe->slope_deg = y.number(n, "slope_deg", 0, -90, 90, p);
  pipe->mesh_segments = static_cast<int>(y.number(n, "mesh_segments", 32, 3, 1024, p));
  if (n["mesh_segments"] && pipe->mesh_segments != n["mesh_segments"].as<double>())
    y.fail(n["mesh_segments"], "'" + p + ".mesh_segments' must be an integer");
  pipe->surface = y.text(n, "surface", pipe->surface, p);
  const YAML::Node segs = n["segments"];
  if (!segs) y.fail(n, "'" + p + "' needs 'segments' (a list such as [{type: straight, length_m: 0.5}])");
  if (!segs.IsSequence() || segs.size() == 0)
    y.fail(segs, "'" + p + ".segments' must be a non-empty list of segments");
  // each segment is a collider and mesh pieces: 100 000 would never finish building
  constexpr size_t kMaxSegments = 1000;
  if (segs.size() > kMaxSegments)
    y.fail(segs, "'" + p + ".segments' has " + std::to_string(segs.size()) + " segments, more than the limit of " +
                     std::to_string(kMaxSegments));
  for (size_t i = 0; i < segs.size(); ++i)
    pipe->segments.push_back(
        load_segment(y, segs[i], p + ".segments[" + std::to_string(i) + "]", pipe->inner_diameter_m));
  try {
    layout_pipe(*pipe);
  } catch (const PipeLayoutError& e) {
    if (e.segment() >= 0)
      y.fail(segs[e.segment()], "'" + p + ".segments[" + std::to_string(e.segment()) + "]': " + e.what());
    y.fail(n, "'" + p + "': " + e.what());
  }
}

void load_terrain(const SceneYaml& y, const YAML::Node& n, TerrainSpec* t) {
  const std::string p = "environment.terrain";
  y.keys(n, p, {"amplitude_m", "wavelength_m", "width_m", "length_m", "resolution_m", "walls",
                "wall_height_m", "wall_thickness_m", "surface", "wall_surface"});
  t->amplitude_m = y.number(n, "amplitude_m", t->amplitude_m, 0, 100, p);
  t->wavelength_m = y.positive(n, "wavelength_m", t->wavelength_m, 1000, p);
  t->width_m = y.positive(n, "width_m", t->width_m, 1000, p);
  t->length_m = y.positive(n, "length_m", t->length_m, 10000, p);
  t->resolution_m = y.number(n, "resolution_m", 0, 0, 1000, p);
  t->walls = y.flag(n, "walls", t->walls, p);
  t->wall_height_m = y.positive(n, "wall_height_m", t->wall_height_m, 1000, p);
  t->wall_thickness_m = y.positive(n, "wall_thickness_m", t->wall_thickness_m, 1000, p);
  t->surface = y.text(n, "surface", t->surface, p);
  t->wall_surface = y.text(n, "wall_surface", t->wall_surface, p);
  try {
    validate_terrain(*t);
  } catch (const std::invalid_argument& e) {
    y.fail(n, "'" + p + "': " + e.what());
  }
}

void load_mesh(const SceneYaml& y, const YAML::Node& n, const std::string& base_dir, MeshSpec* m) {
  const std::string p = "environment.mesh";
  y.keys(n, p, {"file", "scale", "position_m", "rpy_deg", "surface"});
  if (!n["file"]) y.fail(n, "'" + p + "' needs 'file' (an STL, OBJ, PLY or glTF file)");
  m->file_as_given = y.text(n, "file", "", p);
  const std::filesystem::path given(m->file_as_given);
  m->file = given.is_absolute() || base_dir.empty() ? given.string()
                                                    : (std::filesystem::path(base_dir) / given).string();
  m->scale = y.positive(n, "scale", 1.0, 1e6, p);
  m->position_m = y.vec3(n, "position_m", m->position_m, p);
  m->rpy_deg = y.vec3(n, "rpy_deg", m->rpy_deg, p, 360.0);
  m->surface = y.text(n, "surface", m->surface, p);
  try {
    TriMesh mesh = load_mesh_file(m->file, m->scale);
    transform_mesh(&mesh, m->position_m, m->rpy_deg * kRadPerDeg);
    m->data = std::make_shared<const TriMesh>(std::move(mesh));
  } catch (const MeshError& e) {
    y.fail(n["file"], "'" + p + ".file': " + e.what());
  }
}

void load_contacts(const SceneYaml& y, const YAML::Node& n, WorldConfig* w) {
  if (!n.IsSequence())
    y.fail(n, "'contacts' must be a list such as [{between: [pipe, module], mu: 0.4}]");
  const std::vector<std::string> env = environment_surfaces(w->environment);
  std::string known;
  for (const auto& s : env) known += s + ", ";
  known += module_surface_name();
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string p = "contacts[" + std::to_string(i) + "]";
    const YAML::Node c = n[i];
    if (!c.IsMap()) y.fail(c, "'" + p + "' must be a mapping such as {between: [pipe, module], mu: 0.4}");
    const YAML::Node b = c["between"];
    if (!b || !b.IsSequence() || b.size() != 2 || !b[0].IsScalar() || !b[1].IsScalar())
      y.fail(b ? b : c, "'" + p + ".between' must be a list of two surface names (known: " + known + ")");
    MaterialPair pair;
    pair.a = b[0].as<std::string>();
    pair.b = b[1].as<std::string>();
    for (int k = 0; k < 2; ++k) {
      const std::string& s = k ? pair.b : pair.a;
      if (s != module_surface_name() && std::find(env.begin(), env.end(), s) == env.end())
        y.fail(b[k], "'" + p + ".between': surface '" + s + "' is not in this scene (known: " + known + ")");
    }
    const bool a_mod = pair.a == module_surface_name(), b_mod = pair.b == module_surface_name();
    if (!a_mod && !b_mod)
      y.fail(b, "'" + p + ".between': environment surfaces never touch each other; pair one with 'module'");
    for (const MaterialPair& q : w->environment.contacts)
      if ((q.a == pair.a && q.b == pair.b) || (q.a == pair.b && q.b == pair.a))
        y.fail(b, "'" + p + ".between': the pair " + pair.a + "-" + pair.b + " is listed twice");
    pair.material = y.material(c, p, a_mod && b_mod ? w->module_contact : w->ground, true);
    w->environment.contacts.push_back(pair);
  }
}

}  // namespace

void load_scene_environment(const std::string& file, const std::string& base_dir,
                            const YAML::Node& e, const YAML::Node& contacts, WorldConfig* world) {
  const SceneYaml y{file};
  EnvironmentConfig& env = world->environment;
  if (e) {
    const std::string p = "environment";
    y.keys(e, p, {"type", "material", "ground_plane", "ground_surface", "pipe", "terrain", "mesh"});
    const std::string type = y.choice(e, "type", "plane", {"plane", "terrain", "pipe", "mesh"}, p);
    env.type = type == "terrain" ? EnvironmentType::Terrain
               : type == "pipe"  ? EnvironmentType::Pipe
               : type == "mesh"  ? EnvironmentType::Mesh
                                 : EnvironmentType::Plane;
    if (e["material"]) world->ground = y.material(e["material"], p + ".material", world->ground);
    env.ground_plane = env.type == EnvironmentType::Plane;
    if (e["ground_plane"]) {
      env.ground_plane = y.flag(e, "ground_plane", env.ground_plane, p);
      if (env.type == EnvironmentType::Plane && !env.ground_plane)
        y.fail(e["ground_plane"], "'environment.ground_plane' cannot be false with type: plane");
    }
    env.ground_surface = y.text(e, "ground_surface", env.ground_surface, p);
    for (const char* part : {"pipe", "terrain", "mesh"}) {
      if (e[part] && type != part)
        y.fail(e[part], std::string("'environment.") + part + "' is only used with type: " + part +
                            " (type is '" + type + "')");
      if (!e[part] && type == part)
        y.fail(e, std::string("environment type '") + part + "' needs an 'environment." + part + "' mapping");
    }
    if (env.type == EnvironmentType::Pipe) load_pipe(y, e["pipe"], &env.pipe);
    if (env.type == EnvironmentType::Terrain) load_terrain(y, e["terrain"], &env.terrain);
    if (env.type == EnvironmentType::Mesh) load_mesh(y, e["mesh"], base_dir, &env.mesh);
  }
  if (contacts) load_contacts(y, contacts, world);
}

void load_scene_placement_at(const std::string& file, const YAML::Node& placement,
                             const std::vector<std::string>& chain, WorldConfig* world, ScenePlacement* given) {
  const SceneYaml y{file};
  const YAML::Node at = placement["at"];
  if (!at) {
    if (placement["inset_m"]) y.fail(placement["inset_m"], "'placement.inset_m' needs 'placement.at'");
    return;
  }
  y.choice(placement, "at", "", {"pipe_entry"}, "placement");
  for (const char* k : {"position_m", "heading_deg"})
    if (placement[k])
      y.fail(placement[k], std::string("'placement.") + k + "' cannot be used with 'placement.at'");
  const double inset = y.number(placement, "inset_m", 0.005, 0, 1000, "placement");
  given->at_pipe_entry = true;
  given->inset_m = inset;
  try {
    // compiled here for its length (the run compiles the finished scene's chain again)
    ChainModel model = compile_chain(*world, chain);
    place_chain_at_pipe_entry(world, &model, inset);
  } catch (const std::invalid_argument& e) {
    y.fail(at, std::string("'placement.at: pipe_entry': ") + e.what());
  }
}

}  // namespace chainsim
