// Environment descriptions. See environment.h.
#include "environment/environment.h"

#include <algorithm>
#include <stdexcept>

#include "environment/mesh_loader.h"
#include "environment/pipe_mesh.h"
#include "environment/pipe_path.h"
#include "environment/terrain.h"
#include "model/units.h"

namespace chainsim {

const char* environment_type_name(EnvironmentType t) {
  switch (t) {
    case EnvironmentType::Plane: return "plane";
    case EnvironmentType::Terrain: return "terrain";
    case EnvironmentType::Pipe: return "pipe";
    case EnvironmentType::Mesh: return "mesh";
  }
  return "?";
}

std::vector<std::string> environment_surfaces(const EnvironmentConfig& env) {
  std::vector<std::string> out;
  auto add = [&](const std::string& s) {
    if (std::find(out.begin(), out.end(), s) == out.end()) out.push_back(s);
  };
  if (env.type == EnvironmentType::Plane || env.ground_plane) add(env.ground_surface);
  switch (env.type) {
    case EnvironmentType::Plane: break;
    case EnvironmentType::Terrain:
      add(env.terrain.surface);
      if (env.terrain.walls) add(env.terrain.wall_surface);
      break;
    case EnvironmentType::Pipe: add(env.pipe.surface); break;
    case EnvironmentType::Mesh: add(env.mesh.surface); break;
  }
  return out;
}

Material contact_material(const EnvironmentConfig& env, const std::string& a, const std::string& b,
                          const Material& fallback) {
  for (const MaterialPair& p : env.contacts)
    if ((p.a == a && p.b == b) || (p.a == b && p.b == a)) return p.material;
  return fallback;
}

std::shared_ptr<const TriMesh> environment_mesh(const EnvironmentConfig& env) {
  switch (env.type) {
    case EnvironmentType::Plane: return nullptr;
    case EnvironmentType::Terrain: return std::make_shared<const TriMesh>(terrain_mesh(env.terrain));
    case EnvironmentType::Pipe:
      if (env.pipe.collider != PipeCollider::Mesh) return nullptr;
      return std::make_shared<const TriMesh>(
          pipe_bore_mesh(layout_pipe(env.pipe), env.pipe.mesh_segments));
    case EnvironmentType::Mesh: {
      if (env.mesh.data) return env.mesh.data;
      TriMesh m = load_mesh_file(env.mesh.file, env.mesh.scale);
      transform_mesh(&m, env.mesh.position_m, env.mesh.rpy_deg * kRadPerDeg);
      return std::make_shared<const TriMesh>(std::move(m));
    }
  }
  return nullptr;
}

}  // namespace chainsim
