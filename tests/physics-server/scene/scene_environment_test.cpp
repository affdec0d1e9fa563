// Scene keys of environments (docs/scene-reference.md): pipes, terrain, meshes,
// contacts and placement at a pipe entry load; malformed ones and broken mesh
// files give errors naming file:line:column and the culprit; scene.json
// describes the environment for the viewer.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "environment/environment.h"
#include "environment/mesh_loader.h"
#include "scene/scene.h"
#include "output/scene_json.h"
#include "model/units.h"

namespace chainsim {
namespace {

std::string error_of(const std::string& yaml, const std::string& name = "s.yaml") {
  try {
    load_scene_text(yaml, name);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

#define EXPECT_HAS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

const char* kPipeScene = R"(name: pipe
chain: PPP
environment:
  type: pipe
  pipe:
    inner_diameter_m: 0.03
    collider: analytic
    segments:
      - {type: straight, length_m: 0.5, slope_deg: 30}
      - {type: elbow, bend_radius_m: 0.05, angle_deg: 90, direction_deg: 90}
      - {type: tee, follow: branch, direction_deg: 270}
      - {type: straight, length_m: 0.3}
  material: {mu: 0.6}
contacts:
  - {between: [pipe, module], mu: 0.4, bounce: 0.1}
placement: {at: pipe_entry, inset_m: 0.01}
)";

TEST(SceneEnvironment, PipeSceneLoadsWithContactsAndEntryPlacement) {
  const Scene s = load_scene_text(kPipeScene, "s.yaml");
  const EnvironmentConfig& e = s.world.environment;
  EXPECT_EQ(e.type, EnvironmentType::Pipe);
  EXPECT_FALSE(e.ground_plane);
  EXPECT_DOUBLE_EQ(e.pipe.inner_diameter_m, 0.03);
  ASSERT_EQ(e.pipe.segments.size(), 4u);
  EXPECT_EQ(e.pipe.segments[2].type, PipeSegment::Type::Tee);
  EXPECT_TRUE(e.pipe.segments[2].follow_branch);
  EXPECT_DOUBLE_EQ(e.pipe.segments[2].run_length_m, 0.09);  // default 3 diameters
  EXPECT_DOUBLE_EQ(s.world.ground.mu, 0.6);
  ASSERT_EQ(e.contacts.size(), 1u);
  EXPECT_DOUBLE_EQ(e.contacts[0].material.mu, 0.4);
  EXPECT_DOUBLE_EQ(e.contacts[0].material.soft_erp, 0.2);  // unset keys from environment.material
  ASSERT_TRUE(s.world.head_orientation.has_value());
  // three passive modules (46 mm) 10 mm into a 30 degree pipe: head 0.148 m up the axis
  const Eigen::Vector3d axis(std::cos(kPi / 6), 0, 0.5);
  EXPECT_NEAR((s.world.head_position - 0.148 * axis).norm(), 0, 1e-12);
  EXPECT_NEAR((*s.world.head_orientation * Eigen::Vector3d::UnitX() - axis).norm(), 0, 1e-12);
}

TEST(SceneEnvironment, TerrainSceneLoadsWithDefaults) {
  const Scene s = load_scene_text(
      "chain: R\nenvironment:\n  type: terrain\n  terrain: {amplitude_m: 0.03, walls: false}\n", "s.yaml");
  const TerrainSpec& t = s.world.environment.terrain;
  EXPECT_EQ(s.world.environment.type, EnvironmentType::Terrain);
  EXPECT_DOUBLE_EQ(t.amplitude_m, 0.03);
  EXPECT_DOUBLE_EQ(t.wavelength_m, 0.25);
  EXPECT_FALSE(t.walls);
}

TEST(SceneEnvironment, MeshPathIsRelativeToTheSceneFile) {
  const std::string dir = std::string(CHAINSIM_SOURCE_DIR) + "/scenes";
  const Scene s = load_scene_text(
      "chain: R\nenvironment:\n  type: mesh\n  mesh: {file: meshes/straight-pipe.stl, scale: 2, "
      "position_m: [0, 0, 0.1], rpy_deg: [0, 0, 90]}\n",
      dir + "/x.yaml");
  const MeshSpec& m = s.world.environment.mesh;
  EXPECT_EQ(m.file, dir + "/meshes/straight-pipe.stl");
  ASSERT_TRUE(m.data);
  // the straight pipe runs 0.2 m along +x from the origin: scaled x2, turned
  // 90 degrees about z (now along +y), raised 0.1 m
  EXPECT_NEAR(m.data->max_corner().y(), 0.4, 1e-6);
  EXPECT_NEAR(m.data->min_corner().y(), 0.0, 1e-6);
  EXPECT_NEAR(m.data->min_corner().z() + m.data->max_corner().z(), 0.2, 1e-6);
}

TEST(SceneEnvironment, ShippedScenesLoad) {
  int n = 0;
  for (const auto& f : std::filesystem::directory_iterator(std::string(CHAINSIM_SOURCE_DIR) + "/scenes")) {
    if (f.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(load_scene_file(f.path().string())) << f.path();
    ++n;
  }
  EXPECT_GE(n, 4);
}

TEST(SceneEnvironment, SplitLoadsAndNeedsItsBendRadius) {
  const std::string head = "chain: R\nenvironment:\n  type: pipe\n  pipe:\n    segments:\n"
                           "      - {type: straight, length_m: 0.3}\n";
  const Scene s = load_scene_text(head + "      - {type: split, bend_radius_m: 0.16, direction_deg: 270}\n", "s.yaml");
  const PipeSegment& g = s.world.environment.pipe.segments[1];
  EXPECT_EQ(g.type, PipeSegment::Type::Split);
  EXPECT_DOUBLE_EQ(g.bend_radius_m, 0.16);
  EXPECT_DOUBLE_EQ(g.angle_deg, 90);
  EXPECT_DOUBLE_EQ(g.direction_deg, 270);
  std::string e = error_of(head + "      - {type: split, direction_deg: 90}\n");
  EXPECT_HAS(e, "s.yaml:7:9");
  EXPECT_HAS(e, "(split) needs 'bend_radius_m'");
  e = error_of(head + "      - {type: split, bend_radius_m: 0.16, follow: run}\n");
  EXPECT_HAS(e, "unknown key 'follow'");
}

TEST(SceneEnvironment, UnknownKeysAreNamedWithTheirPlace) {
  std::string e = error_of("chain: R\nenvironment:\n  type: pipe\n  pipe:\n    diameter: 0.03\n");
  EXPECT_HAS(e, "s.yaml:5:5");
  EXPECT_HAS(e, "unknown key 'diameter' in 'environment.pipe'");
  EXPECT_HAS(e, "inner_diameter_m");  // the known keys are listed
  e = error_of("chain: R\nenvironment:\n  type: pipe\n  pipe:\n    segments:\n      - {type: straight, lenght_m: 1}\n");
  EXPECT_HAS(e, "s.yaml:6:26");
  EXPECT_HAS(e, "'lenght_m' in 'environment.pipe.segments[0]'");
  e = error_of("chain: R\nenvironment: {type: cave}\n");
  EXPECT_HAS(e, "s.yaml:2:21");
  EXPECT_HAS(e, "'cave' is not known (known: plane, terrain, pipe, mesh)");
  e = error_of("chain: R\nenvironment: {type: terrain, terrain: {hills: 3}}\n");
  EXPECT_HAS(e, "unknown key 'hills' in 'environment.terrain'");
}

TEST(SceneEnvironment, BadValuesAreNamed) {
  std::string e = error_of(
      "chain: R\nenvironment:\n  type: pipe\n  pipe:\n    inner_diameter_m: -0.03\n    segments: [{type: straight, length_m: 1}]\n");
  EXPECT_HAS(e, "s.yaml:5:23");
  EXPECT_HAS(e, "'environment.pipe.inner_diameter_m' = -0.03 must be > 0");
  e = error_of(
      "chain: R\nenvironment:\n  type: pipe\n  pipe:\n    segments:\n      - {type: straight, length_m: 0.2}\n"
      "      - {type: elbow, bend_radius_m: 0.01}\n");
  EXPECT_HAS(e, "s.yaml:7:9");
  EXPECT_HAS(e, "segments[1]");
  EXPECT_HAS(e, "bend_radius_m must be larger than the inner radius");
  e = error_of(
      "chain: R\nenvironment:\n  type: pipe\n  pipe:\n    segments:\n      - {type: straight, length_m: 0.2}\n"
      "      - {type: straight, length_m: 0.2, slope_deg: 10}\n");
  EXPECT_HAS(e, "segments[1]");
  EXPECT_HAS(e, "only allowed on the first segment");
  e = error_of("chain: R\nenvironment:\n  type: pipe\n  pipe:\n    segments: [{type: bend}]\n");
  EXPECT_HAS(e, "'bend' is not known (known: straight, elbow, tee, split)");
  EXPECT_EQ(error_of("chain: R\nenvironment: {type: pipe}\n"),
            "s.yaml:2:14: environment type 'pipe' needs an 'environment.pipe' mapping");
  EXPECT_EQ(error_of("chain: R\nenvironment: {type: plane, pipe: {}}\n"),
            "s.yaml:2:34: 'environment.pipe' is only used with type: pipe (type is 'plane')");
  e = error_of("chain: R\nenvironment: {type: terrain, terrain: {width_m: -1}}\n");
  EXPECT_HAS(e, "'environment.terrain.width_m' = -1 must be > 0");
}

TEST(SceneEnvironment, ContactsNameUnknownSurfacesAndRepeats) {
  std::string e = error_of("chain: R\ncontacts:\n  - {between: [steel, module], mu: 0.4}\n");
  EXPECT_HAS(e, "s.yaml:3:16");
  EXPECT_HAS(e, "surface 'steel' is not in this scene (known: ground, module)");
  EXPECT_EQ(error_of("chain: R\ncontacts:\n  - {between: [ground, module]}\n  - {between: [module, ground]}\n"),
            "s.yaml:4:15: 'contacts[1].between': the pair module-ground is listed twice");
  EXPECT_EQ(error_of("chain: R\nenvironment: {type: terrain, terrain: {}}\ncontacts:\n"
                     "  - {between: [ground, wall]}\n"),
            "s.yaml:4:15: 'contacts[0].between': environment surfaces never touch each other; pair one "
            "with 'module'");
  e = error_of("chain: R\ncontacts:\n  - {between: [ground, module], friction: 1}\n");
  EXPECT_HAS(e, "unknown key 'friction' in 'contacts[0]'");
}

TEST(SceneEnvironment, PlacementAtThePipeEntryNeedsAPipeThatFits) {
  EXPECT_EQ(error_of("chain: R\nplacement: {at: pipe_entry}\n"),
            "s.yaml:2:17: 'placement.at: pipe_entry': placement at the pipe entry needs environment type "
            "'pipe'");
  // four passive modules (4 x 46 mm) and the default 5 mm inset in a 0.1 m straight
  EXPECT_EQ(error_of("chain: PPPP\nenvironment:\n  type: pipe\n  pipe: {segments: [{type: straight, "
                     "length_m: 0.1}]}\nplacement: {at: pipe_entry}\n"),
            "s.yaml:5:17: 'placement.at: pipe_entry': the chain (0.184 m) plus the inset (0.005 m) does "
            "not fit in the pipe's first straight segment (0.1 m; it must start with a straight segment "
            "at least that long)");
  // two fit in 0.1 m
  EXPECT_EQ(error_of("chain: PP\nenvironment:\n  type: pipe\n  pipe: {segments: [{type: straight, "
                     "length_m: 0.1}]}\nplacement: {at: pipe_entry}\n"),
            "(no error)");
  EXPECT_EQ(error_of("chain: R\nplacement: {at: pipe_entry, heading_deg: 10}\n"),
            "s.yaml:2:42: 'placement.heading_deg' cannot be used with 'placement.at'");
  const std::string e = error_of("chain: R\nplacement: {at: door}\n");
  EXPECT_EQ(e.rfind("s.yaml:2:17: ", 0), 0u) << e;
  EXPECT_HAS(e, "'door' is not known (known: pipe_entry)");
}

TEST(SceneEnvironment, MissingAndBrokenMeshFilesNameTheFileAndTheReason) {
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("chainsim_scene_env_" + std::to_string(::getpid())))
                              .string();
  std::filesystem::create_directories(dir);
  struct Cleanup {
    std::string dir;
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } cleanup{dir};
  const std::string scene = dir + "/scene.yaml";
  std::string e = error_of("chain: R\nenvironment:\n  type: mesh\n  mesh: {file: nope.stl}\n", scene);
  EXPECT_HAS(e, scene + ":4:16");
  EXPECT_HAS(e, "'environment.mesh.file'");
  EXPECT_HAS(e, dir + "/nope.stl");
  EXPECT_HAS(e, "no such file");
  std::ofstream(dir + "/broken.obj") << "v 0 0 0\nf 1 2 3\n";  // a face of vertices that do not exist
  e = error_of("chain: R\nenvironment:\n  type: mesh\n  mesh: {file: broken.obj}\n", scene);
  EXPECT_HAS(e, dir + "/broken.obj");
  EXPECT_HAS(e, "assimp");
  std::ofstream(dir + "/empty.stl") << "";
  e = error_of("chain: R\nenvironment:\n  type: mesh\n  mesh: {file: empty.stl}\n", scene);
  EXPECT_HAS(e, dir + "/empty.stl");
  e = error_of("chain: R\nenvironment:\n  type: mesh\n  mesh: {scale: 1}\n", scene);
  EXPECT_HAS(e, "needs 'file'");
}

TEST(SceneEnvironment, SceneJsonDescribesThePipe) {
  const Scene s = load_scene_text(kPipeScene, "s.yaml");
  const nlohmann::json j = scene_json(s, compile_chain(s))["environment"];
  EXPECT_EQ(j["type"], "pipe");
  EXPECT_DOUBLE_EQ(j["material"]["mu"].get<double>(), 0.6);
  EXPECT_EQ(j["contacts"][0]["between"][0], "pipe");
  const auto& pieces = j["pipe"]["pieces"];
  ASSERT_EQ(pieces.size(), 5u);  // straight, elbow, tee run, tee branch, straight
  EXPECT_EQ(pieces[1]["type"], "elbow");
  EXPECT_DOUBLE_EQ(pieces[1]["bend_radius_m"].get<double>(), 0.05);
  EXPECT_TRUE(pieces[2]["tee"].get<bool>());
  EXPECT_DOUBLE_EQ(j["pipe"]["inner_radius_m"].get<double>(), 0.015);
  EXPECT_EQ(j["pipe"]["open_ends"].size(), 3u);
}

}  // namespace
}  // namespace chainsim
