// Whether two Scenes are the same scene: scene_differences (scene_write.h).
//
// Every struct is taken apart with a structured binding, which names each of
// its fields: adding a field to one of them stops this file compiling until
// the field is compared here. Compare it, write it in write_scene
// (scene_write.cpp), and set it in the scene of every key in
// tests/physics-server/scene/scene_write_test.cpp, whose round trip then
// fails if write_scene leaves it out.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <type_traits>

#include "environment/mesh_loader.h"
#include "scene/scene_write.h"

namespace chainsim {

namespace {

class Differences {
 public:
  std::vector<std::string> found;

  void same(const std::string& what, bool equal) {
    if (!equal) found.push_back(what);
  }
  void num(const std::string& what, double a, double b) {
    same(what, a == b ? std::signbit(a) == std::signbit(b) : std::isnan(a) && std::isnan(b));
  }
  void vec(const std::string& what, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    for (int i = 0; i < 3; ++i) num(what + "[" + std::to_string(i) + "]", a[i], b[i]);
  }
  template <typename T>
  void eq(const std::string& what, const T& a, const T& b) {
    same(what, a == b);
  }
  // files as the files they name: from any directory
  void file(const std::string& what, const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return eq(what, a, b);  // no file
    same(what, std::filesystem::absolute(a).lexically_normal() == std::filesystem::absolute(b).lexically_normal());
  }
  // a program given as a path is a file, a bare name a name
  void program(const std::string& what, const std::string& a, const std::string& b) {
    if (a.find('/') != std::string::npos && b.find('/') != std::string::npos)
      file(what, a, b);
    else
      eq(what, a, b);
  }

  void material(const std::string& p, const Material& a, const Material& b) {
    const auto& [mu, bounce, soft_erp, soft_cfm] = a;
    num(p + ".mu", mu, b.mu);
    num(p + ".bounce", bounce, b.bounce);
    num(p + ".soft_erp", soft_erp, b.soft_erp);
    num(p + ".soft_cfm", soft_cfm, b.soft_cfm);
  }

  void module(const std::string& p, const SceneModule& a, const SceneModule& b) {
    const auto& [type, firmware, params, param_at, firmware_at, target, target_at, may_stay_silent] = a;
    (void)param_at, (void)firmware_at, (void)target_at;  // where the file says it
    eq(p + ".type", type, b.type);
    program(p + ".firmware", firmware, b.firmware);
    eq(p + ".params", params, b.params);
    eq(p + ".target", target, b.target);
    eq(p + ".may_stay_silent", may_stay_silent, b.may_stay_silent);
  }

  void program_defaults(const std::string& p, const SceneProgram& a, const SceneProgram& b) {
    const auto& [firmware, firmware_at, target, target_at, may_stay_silent, params, param_at] = a;
    (void)firmware_at, (void)target_at, (void)param_at;
    program(p + ".firmware", firmware, b.firmware);
    eq(p + ".target", target, b.target);
    eq(p + ".may_stay_silent", may_stay_silent, b.may_stay_silent);
    eq(p + ".params", params, b.params);
  }

  void stop_rule(const std::string& p, const StopRule& a, const StopRule& b) {
    const auto& [kind, tail, along_pipe, axis, by_m, within_s, reach_m, by_s, along_given] = a;
    eq(p + ".kind", kind, b.kind);
    eq(p + ".tail", tail, b.tail);
    eq(p + ".along_pipe", along_pipe, b.along_pipe);
    vec(p + ".axis", axis, b.axis);
    num(p + ".by_m", by_m, b.by_m);
    num(p + ".within_s", within_s, b.within_s);
    num(p + ".reach_m", reach_m, b.reach_m);
    num(p + ".by_s", by_s, b.by_s);
    same(p + ".along_given", along_given.has_value() == b.along_given.has_value());
    if (along_given && b.along_given) vec(p + ".along_given", *along_given, *b.along_given);
  }

  void segment(const std::string& p, const PipeSegment& a, const PipeSegment& b) {
    const auto& [type, length_m, slope_deg, bend_radius_m, angle_deg, direction_deg, run_length_m, branch_length_m,
                 follow_branch] = a;
    eq(p + ".type", type, b.type);
    num(p + ".length_m", length_m, b.length_m);
    num(p + ".slope_deg", slope_deg, b.slope_deg);
    num(p + ".bend_radius_m", bend_radius_m, b.bend_radius_m);
    num(p + ".angle_deg", angle_deg, b.angle_deg);
    num(p + ".direction_deg", direction_deg, b.direction_deg);
    num(p + ".run_length_m", run_length_m, b.run_length_m);
    num(p + ".branch_length_m", branch_length_m, b.branch_length_m);
    eq(p + ".follow_branch", follow_branch, b.follow_branch);
  }

  void pipe(const std::string& p, const PipeSpec& a, const PipeSpec& b) {
    const auto& [inner_diameter_m, collider, entry_m, heading_deg, slope_deg, segments, mesh_segments, surface] = a;
    num(p + ".inner_diameter_m", inner_diameter_m, b.inner_diameter_m);
    eq(p + ".collider", collider, b.collider);
    vec(p + ".entry_m", entry_m, b.entry_m);
    num(p + ".heading_deg", heading_deg, b.heading_deg);
    num(p + ".slope_deg", slope_deg, b.slope_deg);
    eq(p + ".segments.size", segments.size(), b.segments.size());
    for (size_t i = 0; i < segments.size() && i < b.segments.size(); ++i)
      segment(p + ".segments[" + std::to_string(i) + "]", segments[i], b.segments[i]);
    eq(p + ".mesh_segments", mesh_segments, b.mesh_segments);
    eq(p + ".surface", surface, b.surface);
  }

  void terrain(const std::string& p, const TerrainSpec& a, const TerrainSpec& b) {
    const auto& [amplitude_m, wavelength_m, width_m, length_m, resolution_m, walls, wall_height_m, wall_thickness_m,
                 surface, wall_surface] = a;
    num(p + ".amplitude_m", amplitude_m, b.amplitude_m);
    num(p + ".wavelength_m", wavelength_m, b.wavelength_m);
    num(p + ".width_m", width_m, b.width_m);
    num(p + ".length_m", length_m, b.length_m);
    num(p + ".resolution_m", resolution_m, b.resolution_m);
    eq(p + ".walls", walls, b.walls);
    num(p + ".wall_height_m", wall_height_m, b.wall_height_m);
    num(p + ".wall_thickness_m", wall_thickness_m, b.wall_thickness_m);
    eq(p + ".surface", surface, b.surface);
    eq(p + ".wall_surface", wall_surface, b.wall_surface);
  }

  void mesh(const std::string& p, const MeshSpec& a, const MeshSpec& b) {
    const auto& [file_, file_as_given, scale, position_m, rpy_deg, surface, data] = a;
    (void)file_as_given;  // as the file writes it
    file(p + ".file", file_, b.file);
    num(p + ".scale", scale, b.scale);
    vec(p + ".position_m", position_m, b.position_m);
    vec(p + ".rpy_deg", rpy_deg, b.rpy_deg);
    eq(p + ".surface", surface, b.surface);
    // the loaded triangles: the same file found and placed the same way
    same(p + ".data", !data == !b.data);
    if (data && b.data) {
      same(p + ".data.triangles", data->triangles == b.data->triangles);
      same(p + ".data.vertices", data->vertices.size() == b.data->vertices.size());
      for (size_t i = 0; i < data->vertices.size() && i < b.data->vertices.size(); ++i)
        if (data->vertices[i] != b.data->vertices[i]) {
          same(p + ".data.vertices[" + std::to_string(i) + "]", false);
          break;
        }
    }
  }

  void environment(const std::string& p, const EnvironmentConfig& a, const EnvironmentConfig& b) {
    const auto& [type, ground_plane, ground_surface, pipe_, terrain_, mesh_, contacts] = a;
    eq(p + ".type", type, b.type);
    eq(p + ".ground_plane", ground_plane, b.ground_plane);
    eq(p + ".ground_surface", ground_surface, b.ground_surface);
    pipe(p + ".pipe", pipe_, b.pipe);
    terrain(p + ".terrain", terrain_, b.terrain);
    mesh(p + ".mesh", mesh_, b.mesh);
    eq(p + ".contacts.size", contacts.size(), b.contacts.size());
    for (size_t i = 0; i < contacts.size() && i < b.contacts.size(); ++i) {
      const std::string q = p + ".contacts[" + std::to_string(i) + "]";
      const auto& [pa, pb, m] = contacts[i];
      eq(q + ".a", pa, b.contacts[i].a);
      eq(q + ".b", pb, b.contacts[i].b);
      material(q + ".material", m, b.contacts[i].material);
    }
  }

  void world(const std::string& p, const WorldConfig& a, const WorldConfig& b) {
    const auto& [dt_us, seed, head_position, heading_rad, roll_rad, head_orientation, ground, module_contact, env,
                 servo, gravity_m_s2, solver_iterations, solver, dock, module_types] = a;
    eq(p + ".dt_us", dt_us, b.dt_us);
    eq(p + ".seed", seed, b.seed);
    vec(p + ".head_position", head_position, b.head_position);
    num(p + ".heading_rad", heading_rad, b.heading_rad);
    num(p + ".roll_rad", roll_rad, b.roll_rad);
    same(p + ".head_orientation", head_orientation.has_value() == b.head_orientation.has_value());
    if (head_orientation && b.head_orientation)
      for (int i = 0; i < 4; ++i)
        num(p + ".head_orientation[" + std::to_string(i) + "]", head_orientation->coeffs()[i],
            b.head_orientation->coeffs()[i]);
    material(p + ".ground", ground, b.ground);
    material(p + ".module_contact", module_contact, b.module_contact);
    environment(p + ".environment", env, b.environment);
    // no scene key sets the servo model (a bench file does): all doubles, compared bit for bit
    static_assert(std::is_trivially_copyable_v<ServoParams> && sizeof(ServoParams) % sizeof(double) == 0);
    same(p + ".servo", std::memcmp(&servo, &b.servo, sizeof servo) == 0);
    num(p + ".gravity_m_s2", gravity_m_s2, b.gravity_m_s2);
    eq(p + ".solver_iterations", solver_iterations, b.solver_iterations);
    eq(p + ".solver", solver, b.solver);
    same(p + ".dock", dock.has_value() == b.dock.has_value());
    if (dock && b.dock) {
      const auto& [play_deg, stiffness, damping] = *dock;
      num(p + ".dock.play_deg", play_deg, b.dock->play_deg);
      num(p + ".dock.stiffness_nm_per_rad", stiffness, b.dock->stiffness_nm_per_rad);
      num(p + ".dock.damping_nm_s_per_rad", damping, b.dock->damping_nm_s_per_rad);
    }
    // module types: a definition is what its file says (Scene::module_type_files); here their names in order
    eq(p + ".module_types.size", module_types.size(), b.module_types.size());
    for (size_t i = 0; i < module_types.size() && i < b.module_types.size(); ++i)
      eq(p + ".module_types[" + std::to_string(i) + "].type", module_types[i].type, b.module_types[i].type);
  }
};

}  // namespace

std::vector<std::string> scene_differences(const Scene& a, const Scene& b) {
  Differences d;
  const auto& [source, name, duration_s, tick_us, world, modules, central, discovery_s, trace_hz, pic, stop_when,
               module_type_files, programs, target, target_at, placement] = a;
  (void)source, (void)target_at;  // where the scene came from, where it says its target
  d.eq("name", name, b.name);
  d.num("duration_s", duration_s, b.duration_s);
  d.eq("tick_us", tick_us, b.tick_us);
  d.world("world", world, b.world);
  d.eq("modules.size", modules.size(), b.modules.size());
  for (size_t i = 0; i < modules.size() && i < b.modules.size(); ++i)
    d.module("modules[" + std::to_string(i) + "]", modules[i], b.modules[i]);
  d.module("central", central, b.central);
  d.num("discovery_s", discovery_s, b.discovery_s);
  d.num("trace_hz", trace_hz, b.trace_hz);
  const auto& [cpu_budget_us, stall_ms] = pic;
  d.eq("pic.cpu_budget_us", cpu_budget_us, b.pic.cpu_budget_us);
  d.eq("pic.stall_ms", stall_ms, b.pic.stall_ms);
  d.eq("stop_when.size", stop_when.size(), b.stop_when.size());
  for (size_t i = 0; i < stop_when.size() && i < b.stop_when.size(); ++i)
    d.stop_rule("stop_when[" + std::to_string(i) + "]", stop_when[i], b.stop_when[i]);
  d.eq("module_type_files.size", module_type_files.size(), b.module_type_files.size());
  for (size_t i = 0; i < module_type_files.size() && i < b.module_type_files.size(); ++i) {
    const std::string p = "module_type_files[" + std::to_string(i) + "]";
    d.eq(p + ".name", module_type_files[i].first, b.module_type_files[i].first);
    d.file(p + ".file", module_type_files[i].second, b.module_type_files[i].second);
  }
  d.eq("programs.size", programs.size(), b.programs.size());
  for (const auto& [type, p] : programs) {
    const auto it = b.programs.find(type);
    d.same("programs." + type, it != b.programs.end());
    if (it != b.programs.end()) d.program_defaults("programs." + type, p, it->second);
  }
  d.eq("target", target, b.target);
  const auto& [at_pipe_entry, inset_m, position_m, heading_deg, roll_deg] = placement;
  d.eq("placement.at_pipe_entry", at_pipe_entry, b.placement.at_pipe_entry);
  d.num("placement.inset_m", inset_m, b.placement.inset_m);
  d.vec("placement.position_m", position_m, b.placement.position_m);
  d.num("placement.heading_deg", heading_deg, b.placement.heading_deg);
  d.num("placement.roll_deg", roll_deg, b.placement.roll_deg);
  return d.found;
}

}  // namespace chainsim
