// write_scene and the edits of scene_edit.h: a written scene reads back to
// the same Scene (scene_differences empty) from another directory, for every
// shipped scene and for scenes that set every key, among them every key that
// holds a path; the edits a design search makes, and their errors.
#include <gtest/gtest.h>

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene/scene_edit.h"
#include "scene/scene_write.h"

namespace fs = std::filesystem;
using namespace chainsim;

namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + " ";
  return s;
}

void write_file(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// a fresh directory of this test's own
fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("chainsim-scene-write-" + std::to_string(getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// s written, read back from elsewhere/deeper/scene.yaml, written again
void expect_round_trip(const Scene& s, const fs::path& elsewhere) {
  const std::string text = write_scene(s);
  const fs::path file = elsewhere / "deeper" / "scene.yaml";
  write_file(file, text);
  Scene again;
  ASSERT_NO_THROW(again = load_scene_file(file.string())) << s.source << "\n" << text;
  EXPECT_EQ(scene_differences(s, again), std::vector<std::string>{}) << s.source << "\n" << text;
  EXPECT_EQ(write_scene(again), text) << s.source;
}

// every scene under scenes/ (problem files and module, bench files are not)
std::vector<fs::path> shipped_scenes() {
  std::vector<fs::path> out;
  for (const char* dir : {"scenes", "scenes/optimize"})
    for (const auto& e : fs::directory_iterator(fs::path(CHAINSIM_SOURCE_DIR) / dir)) {
      if (e.path().extension() != ".yaml") continue;
      const YAML::Node root = YAML::LoadFile(e.path().string());
      if (!root["genome"]) out.push_back(e.path());
    }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(SceneWrite, EveryShippedSceneReadsBackTheSame) {
  const fs::path elsewhere = scratch("shipped");
  const std::vector<fs::path> files = shipped_scenes();
  EXPECT_GE(files.size(), 25u);
  for (const fs::path& f : files) expect_round_trip(load_scene_file(f.string()), elsewhere / f.stem());
  expect_round_trip(default_scene(), elsewhere / "default");
  // loaded by a relative name, as `chainsim run scenes/x.yaml` does (its
  // paths are relative to the working directory, which must not change
  // before it is written)
  const fs::path cwd = fs::current_path();
  fs::current_path(CHAINSIM_SOURCE_DIR);
  expect_round_trip(load_scene_file("scenes/mesh-pipe.yaml"), elsewhere / "relative");
  fs::current_path(cwd);
}

// every key, and every key that holds a path, relative to the scene's
// directory: written to another directory, the scene still finds its module
// types, mesh and programs
TEST(SceneWrite, EveryKeyAndEveryPathReadsBackTheSame) {
  const fs::path dir = scratch("every-key");
  const fs::path src = fs::path(CHAINSIM_SOURCE_DIR) / "scenes";
  {  // a type of the scene's own: rotation renamed
    std::ifstream in(src / "modules/rotation.yaml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t at = text.find("type: rotation");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 14, "type: wide");
    write_file(dir / "types/wide.yaml", text);
  }
  fs::create_directories(dir / "meshes");
  fs::copy_file(src / "meshes/straight-pipe.stl", dir / "meshes/pipe.stl");
  const std::string common = R"(
module_types: {wide: types/wide.yaml}
programs:
  all: {params: {gait: 3}, may_stay_silent: true}
  rotation: {firmware: ../bin/fw-rot, params: {gait: 4, amp: 7}, target: pic}
  wide: {firmware: fw-wide}
target: native
chain:
  - {type: rotation, params: {amp: 9}}
  - {type: wide, firmware: ./fw/own, may_stay_silent: false, target: pic}
  - {type: touch}
central: {program: ../bin/fw-c, params: {gait: 2, x: -5}, discovery_s: 0.25, target: pic}
pic: {cpu_budget_us: 700, stall_ms: 1500}
output: {trace_hz: 33.3}
name: every_key
duration_s: 2.7
seed: 123456789012345
physics: {dt_us: 250, tick_us: 750, gravity_m_s2: 9.80665, solver_iterations: 41,
          dock: {play_deg: 0.7, stiffness_n_m_per_rad: 1500.5, damping_n_m_s_per_rad: 0.25}}
)";
  const std::string mesh = common + R"(
environment:
  type: mesh
  ground_plane: true
  ground_surface: floor
  material: {mu: 0.7, bounce: 0.1, soft_erp: 0.3, soft_cfm: 0.00002}
  mesh: {file: meshes/pipe.stl, scale: 1.0, position_m: [0.0, 0.0, 0.017], rpy_deg: [0, 0, 0.1], surface: pvc}
contacts:
  - {between: [pvc, module], mu: 0.5, bounce: 0.05}
  - {between: [module, module], mu: 0.31}
placement: {position_m: [0.15, 0.01, 0.017], heading_deg: 1.7, roll_deg: -3.3}
stop_when:
  - {no_progress: {of: tail, along: [1, 1, 0.1], by_m: 0.01, within_s: 1.5}}
  - {not_reached: {of: head, along: y, reach_m: -0.3, by_s: 2}}
)";
  const std::string pipe = common + R"(
environment:
  type: pipe
  pipe:
    inner_diameter_m: 0.04
    collider: mesh
    entry_m: [0.1, 0.2, 0.3]
    heading_deg: 10
    slope_deg: 5
    mesh_segments: 24
    surface: pvc
    segments:
      - {type: straight, length_m: 0.6, slope_deg: 4}
      - {type: elbow, bend_radius_m: 0.08, angle_deg: 45, direction_deg: 90}
      - {type: tee, run_length_m: 0.2, branch_length_m: 0.1, direction_deg: 180, follow: branch}
      - {type: split, bend_radius_m: 0.08, direction_deg: 270}
      - {type: straight, length_m: 0.1}
placement: {at: pipe_entry, inset_m: 0.01, roll_deg: 12}
stop_when:
  - {no_progress: {of: head, along: pipe, by_m: 0.01, within_s: 1.5}}
)";
  const std::string terrain = common + R"(
environment:
  type: terrain
  ground_plane: true
  terrain: {amplitude_m: 0.01, wavelength_m: 0.3, width_m: 0.4, length_m: 3, resolution_m: 0.01, walls: false,
            wall_height_m: 0.06, wall_thickness_m: 0.02, surface: sand, wall_surface: brick}
)";
  int k = 0;
  for (const std::string& text : {mesh, pipe, terrain}) {
    const fs::path file = dir / ("scene-" + std::to_string(k++) + ".yaml");
    write_file(file, text);
    const Scene s = load_scene_file(file.string());
    expect_round_trip(s, dir / "elsewhere" / file.stem());
    // the paths as loading resolved them, written absolute
    const std::string written = write_scene(s);
    const std::string abs = fs::absolute(dir).lexically_normal().string();
    for (const std::string& p : {abs + "/types/wide.yaml", fs::absolute(dir / "../bin/fw-rot").lexically_normal().string(),
                                 abs + "/fw/own", fs::absolute(dir / "../bin/fw-c").lexically_normal().string()})
      EXPECT_NE(written.find(p), std::string::npos) << p << " in\n" << written;
    EXPECT_NE(written.find("firmware: fw-wide"), std::string::npos) << "a bare program name stays a name";
    if (k == 1) {
      EXPECT_NE(written.find(abs + "/meshes/pipe.stl"), std::string::npos);
    }
  }
}

// a field the round trip would miss shows as a difference
TEST(SceneWrite, DifferencesNameTheField) {
  const Scene a = load_scene_text("chain: RR\n", "s.yaml");
  Scene b = a;
  EXPECT_TRUE(scene_differences(a, b).empty());
  b.world.environment.terrain.wall_surface = "x";
  b.modules[1].params["gait"] = 2;
  b.pic.stall_ms = 1;
  EXPECT_EQ(joined(scene_differences(a, b)), "world.environment.terrain.wall_surface modules[1].params pic.stall_ms ");
}

// set_chain: each module of the new chain as `programs` gives its type; a
// scene at a pipe's entry is placed again for the new chain
TEST(SceneEdit, ChainTakesItsTypesProgramsAndIsPlacedAgain) {
  const fs::path dir = scratch("edit-chain");
  const auto scene_of = [](const std::string& chain) {
    return R"(
environment: {type: pipe, pipe: {inner_diameter_m: 0.04, segments: [{type: straight, length_m: 1}]}}
programs:
  all: {params: {gait: 3}}
  rotation: {firmware: ../bin/fw-rot, params: {amp: 7}}
placement: {at: pipe_entry}
chain: )" + chain + "\n";
  };
  write_file(dir / "s.yaml", scene_of("TR"));
  Scene s = load_scene_file((dir / "s.yaml").string());
  set_chain(&s, "RRT");
  ASSERT_EQ(s.modules.size(), 3u);
  EXPECT_EQ(s.modules[1].firmware, (dir / "../bin/fw-rot").string());
  EXPECT_EQ(s.modules[1].params, (std::map<std::string, int32_t>{{"amp", 7}, {"gait", 3}}));
  EXPECT_EQ(s.modules[2].firmware, "fw-touch");
  // the same as the file with that chain says
  write_file(dir / "t.yaml", scene_of("RRT"));
  EXPECT_EQ(scene_differences(s, load_scene_file((dir / "t.yaml").string())), std::vector<std::string>{});
  expect_round_trip(s, dir / "elsewhere");
  // too long for the pipe's straight
  try {
    set_chain(&s, std::string(40, 'R'));
    FAIL() << "a chain longer than the pipe was placed";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("'placement.at: pipe_entry'"), std::string::npos) << e.what();
  }
}

TEST(SceneEdit, ParamsAndTheirErrorsNameTheCulprit) {
  Scene s = load_scene_text("chain: RRH\ncentral: {params: {gait: 1}}\n", "s.yaml");
  set_module_param(&s, 1, "amp", 50);
  set_all_modules_param(&s, "period_ms", 20);
  set_central_param(&s, "gait", 9);
  EXPECT_EQ(set_program_param(&s, "fw-rotation", "bias", -4), 2);
  EXPECT_EQ(s.modules[1].params, (std::map<std::string, int32_t>{{"amp", 50}, {"bias", -4}, {"period_ms", 20}}));
  EXPECT_EQ(s.modules[2].params, (std::map<std::string, int32_t>{{"period_ms", 20}}));
  EXPECT_EQ(s.central.params.at("gait"), 9);
  const auto error_of = [&](auto edit) {
    try {
      edit();
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error_of([&] { set_module_param(&s, 3, "amp", 1); }), "s.yaml: chain[3]: the chain has 3 modules");
  EXPECT_EQ(error_of([&] { set_central_param(&s, "bad name", 1); }),
            "s.yaml: central: parameter name 'bad name' must be 1 to 15 letters, digits or '_'");
  EXPECT_EQ(error_of([&] { set_all_modules_param(&s, "amp", int64_t{1} << 40); }),
            "s.yaml: chain[*]: parameter 'amp' = 1099511627776 is outside the 32-bit range of a program parameter");
  EXPECT_EQ(error_of([&] { set_chain(&s, "RXR"); }),
            "s.yaml: the chain 'RXR' has unknown module letter 'X' (T touch, R rotation, H helicoidal, S support, "
            "E extension, W traveller, P passive)");
  StopRule r;
  r.along_pipe = true;
  EXPECT_EQ(error_of([&] { add_stop_rule(&s, r); }),
            "s.yaml: a stop_when rule along the pipe, but the environment is not a pipe");
  // the edited scene reads back the same
  expect_round_trip(s, scratch("edit-params"));
}

// set_target: the written scene and a chain set afterwards run on it too
TEST(SceneEdit, TargetHoldsForTheChainSetAfterIt) {
  Scene s = load_scene_text("programs: {rotation: {target: native}}\nchain: RR\n", "s.yaml");
  set_target(&s, Target::Pic);
  set_chain(&s, "RTR");
  for (const SceneModule& m : s.modules) EXPECT_EQ(m.target, Target::Pic) << m.type;
  EXPECT_EQ(s.central.target, Target::Pic);
  expect_round_trip(s, scratch("edit-target"));
}
