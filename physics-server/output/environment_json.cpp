// scene.json "environment" block. All lengths in m, angles in rad unless the
// key says _deg, vectors [x, y, z] in the world frame (z up).
//
//   type            "plane" | "terrain" | "pipe" | "mesh"
//   material        {mu, bounce, soft_erp, soft_cfm}: environment-module contacts
//                   not in `contacts`
//   contacts        [{between: [a, b], mu, bounce, soft_erp, soft_cfm}]
//   surfaces        surface names in use ("module" = every module body)
//   ground_plane    true: a plane z = 0 (draw it); ground_surface its surface name
//   pipe (type pipe):
//     collider      "analytic" | "mesh" (same geometry either way)
//     inner_radius_m, surface
//     entry, exit   {point_m, direction, up}: the axis at the entry (direction
//                   into the pipe) and at the end of the last segment
//     open_ends     [{point_m, direction}]: every open end, direction pointing out
//     pieces        the pipe's bore as pieces, each with segment (index in the
//                   scene's segments), inner_radius_m, start_m, end_m and
//                   up (the frame's up at start_m, for ring orientation):
//       {type: "straight", direction, length_m, tee: bool}
//           axis start_m + s direction, 0 <= s <= length_m; tee: part of a tee
//           (the two pieces of a tee cut openings into each other's wall)
//       {type: "elbow", centre_m, bend_radius_m, u, v, normal, angle_rad}
//           axis centre_m + bend_radius_m (cos a u + sin a v), 0 <= a <= angle_rad
//   terrain (type terrain):
//     amplitude_m, wavelength_m, width_m, length_m, height: the formula
//     z = amplitude_m (1 - cos(2 pi x / wavelength_m)) over
//     x_range_m [-length/2, length/2], y_range_m [-width/2, width/2];
//     surface, wall_surface, walls: [{centre_m, size_m}] boxes (axis-aligned)
//   mesh (type mesh):
//     file (resolved path), file_as_given (as in the scene), scale,
//     position_m, rpy_deg (vertex' = Rz(yaw) Ry(pitch) Rx(roll) (scale vertex)
//     + position_m), surface
#include "output/environment_json.h"

#include "environment/pipe_path.h"
#include "environment/terrain.h"

namespace chainsim {
namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json material_json(const Material& m) {
  return {{"mu", m.mu}, {"bounce", m.bounce}, {"soft_erp", m.soft_erp}, {"soft_cfm", m.soft_cfm}};
}

nlohmann::json frame_json(const PipeFrame& f) {
  return {{"point_m", vec(f.point)}, {"direction", vec(f.tangent)}, {"up", vec(f.up)}};
}

nlohmann::json pipe_json(const PipeSpec& spec) {
  const PipeLayout layout = layout_pipe(spec);
  nlohmann::json pieces = nlohmann::json::array();
  for (const PipePiece& p : layout.pieces) {
    nlohmann::json j = {{"segment", p.segment},
                        {"inner_radius_m", p.radius_m},
                        {"start_m", vec(p.start.point)},
                        {"end_m", vec(pipe_piece_frame(p, 1.0).point)},
                        {"up", vec(p.start.up)}};
    if (p.kind == PipePiece::Kind::Straight) {
      j["type"] = "straight";
      j["direction"] = vec(p.start.tangent);
      j["length_m"] = p.length_m;
      j["tee"] = p.holes[0] >= 0 || p.holes[1] >= 0;
    } else {
      j["type"] = "elbow";
      j["centre_m"] = vec(p.centre);
      j["bend_radius_m"] = p.bend_radius_m;
      j["u"] = vec(p.u);
      j["v"] = vec(p.v);
      j["normal"] = vec(p.normal);
      j["angle_rad"] = p.angle_rad;
    }
    pieces.push_back(j);
  }
  nlohmann::json ends = nlohmann::json::array();
  for (const PipeFrame& f : layout.open_ends)
    ends.push_back({{"point_m", vec(f.point)}, {"direction", vec(f.tangent)}});
  return {{"collider", spec.collider == PipeCollider::Mesh ? "mesh" : "analytic"},
          {"inner_radius_m", layout.radius_m},
          {"surface", spec.surface},
          {"entry", frame_json(layout.entry)},
          {"exit", frame_json(layout.exit)},
          {"open_ends", ends},
          {"pieces", pieces}};
}

nlohmann::json terrain_json(const TerrainSpec& t) {
  nlohmann::json walls = nlohmann::json::array();
  for (const TerrainWall& w : terrain_walls(t))
    walls.push_back({{"centre_m", vec(w.centre_m)}, {"size_m", vec(w.size_m)}});
  return {{"amplitude_m", t.amplitude_m},
          {"wavelength_m", t.wavelength_m},
          {"width_m", t.width_m},
          {"length_m", t.length_m},
          {"height", "z = amplitude_m * (1 - cos(2 * pi * x / wavelength_m))"},
          {"x_range_m", {-0.5 * t.length_m, 0.5 * t.length_m}},
          {"y_range_m", {-0.5 * t.width_m, 0.5 * t.width_m}},
          {"surface", t.surface},
          {"wall_surface", t.wall_surface},
          {"walls", walls}};
}

}  // namespace

nlohmann::json environment_json(const WorldConfig& world) {
  const EnvironmentConfig& env = world.environment;
  nlohmann::json contacts = nlohmann::json::array();
  for (const MaterialPair& p : env.contacts) {
    nlohmann::json j = material_json(p.material);
    j["between"] = {p.a, p.b};
    contacts.push_back(j);
  }
  nlohmann::json out = {{"type", environment_type_name(env.type)},
                        {"material", material_json(world.ground)},
                        {"contacts", contacts},
                        {"surfaces", environment_surfaces(env)},
                        {"ground_plane", env.type == EnvironmentType::Plane || env.ground_plane},
                        {"ground_surface", env.ground_surface}};
  switch (env.type) {
    case EnvironmentType::Plane: break;
    case EnvironmentType::Pipe: out["pipe"] = pipe_json(env.pipe); break;
    case EnvironmentType::Terrain: out["terrain"] = terrain_json(env.terrain); break;
    case EnvironmentType::Mesh:
      out["mesh"] = {{"file", env.mesh.file},
                     {"file_as_given", env.mesh.file_as_given},
                     {"scale", env.mesh.scale},
                     {"position_m", vec(env.mesh.position_m)},
                     {"rpy_deg", vec(env.mesh.rpy_deg)},
                     {"surface", env.mesh.surface}};
      break;
  }
  return out;
}

}  // namespace chainsim
