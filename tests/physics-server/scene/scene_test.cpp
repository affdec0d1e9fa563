// Scene files: what loads, and errors that name file:line:column and the key.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "scene_error_of.h"

using chainsim::load_scene_text;
using chainsim::testing::scene_error_of;

TEST(Scene, BuiltInDefaultIsASnakeOfEightRotationModules) {
  const auto s = chainsim::default_scene();
  ASSERT_EQ(s.modules.size(), 8u);
  for (const auto& m : s.modules) {
    EXPECT_EQ(m.type, "rotation");
    EXPECT_EQ(m.firmware, "fw-rotation");
  }
  EXPECT_EQ(s.chain_types(), std::vector<std::string>(8, "rotation"));
  EXPECT_EQ(s.tick_us, 1000);
  EXPECT_EQ(s.world.dt_us, 500);
  EXPECT_EQ(s.central.firmware, "fw-central");
  EXPECT_EQ(s.central.params.at("gait"), 1);
}

TEST(Scene, ChainLettersBecomeModuleTypes) {
  const auto s = load_scene_text("chain: TRHSEWP\n", "s.yaml");
  const std::vector<std::string> want{"touch", "rotation", "helicoidal", "support", "extension", "traveller", "passive"};
  ASSERT_EQ(s.modules.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(s.modules[i].type, want[i]);
}

// the modules are one list: the World's chain is derived from it
TEST(Scene, ChainTypesFollowTheModuleList) {
  auto s = load_scene_text("chain: RPR\n", "s.yaml");
  EXPECT_EQ(s.chain_types(), (std::vector<std::string>{"rotation", "passive", "rotation"}));
  s.modules.pop_back();
  s.modules[0].type = "touch";
  EXPECT_EQ(s.chain_types(), (std::vector<std::string>{"touch", "passive"}));
}

// one seed: the scene's seed is the world's (ODE, sensor noise, WELCOME)
TEST(Scene, SeedIsTheWorldsSeed) {
  EXPECT_EQ(load_scene_text("chain: R\n", "s.yaml").world.seed, 1u);
  EXPECT_EQ(load_scene_text("chain: R\nseed: 42\n", "s.yaml").world.seed, 42u);
  const std::string e = scene_error_of("chain: R\nseed: -3\n");
  EXPECT_EQ(e.rfind("s.yaml:2:7: ", 0), 0u) << e;
  EXPECT_NE(e.find("'scene.seed' = -3 is out of range"), std::string::npos) << e;
}

TEST(Scene, ExplicitModuleListCarriesFirmwareAndParams) {
  const auto s = load_scene_text(
      "chain:\n  - {type: rotation, params: {control_ms: 15}}\n  - {type: passive, firmware: /opt/fw}\n", "s.yaml");
  ASSERT_EQ(s.modules.size(), 2u);
  EXPECT_EQ(s.modules[0].params.at("control_ms"), 15);
  EXPECT_EQ(s.modules[1].firmware, "/opt/fw");
}

// like mesh and module-type files, a program given by a relative path is
// taken from the scene file's directory, not the working directory
TEST(Scene, RelativeProgramPathsResolveAgainstTheSceneFile) {
  const auto s = load_scene_text(
      "chain:\n  - {type: rotation, firmware: build/fw-mine}\n  - {type: rotation, firmware: /opt/fw}\n"
      "  - {type: rotation, firmware: fw-rotation}\ncentral: {program: ../bin/central}\n",
      "/home/me/project/scenes/s.yaml");
  EXPECT_EQ(s.modules[0].firmware, "/home/me/project/scenes/build/fw-mine");
  EXPECT_EQ(s.modules[1].firmware, "/opt/fw");
  EXPECT_EQ(s.modules[2].firmware, "fw-rotation");  // a name: looked up in --firmware-dir, then beside chainsim
  EXPECT_EQ(s.central.firmware, "/home/me/project/scenes/../bin/central");
}

// programs: the chain's and each type's program and parameters, overridden by a module's own
TEST(Scene, ProgramsGiveEveryModuleAndEveryTypeItsProgramAndParameters) {
  const auto s = load_scene_text(
      "programs:\n"
      "  all: {params: {control_ms: 20, poll_ms: 500}}\n"
      "  rotation: {firmware: /opt/fw-nod, params: {control_ms: 10, amp: 30}}\n"
      "chain:\n"
      "  - {type: rotation}\n"
      "  - {type: rotation, firmware: /opt/other, params: {amp: 45}}\n"
      "  - {type: passive}\n",
      "s.yaml");
  ASSERT_EQ(s.modules.size(), 3u);
  EXPECT_EQ(s.modules[0].firmware, "/opt/fw-nod");
  EXPECT_EQ(s.modules[0].params, (std::map<std::string, int32_t>{{"amp", 30}, {"control_ms", 10}, {"poll_ms", 500}}));
  EXPECT_EQ(s.modules[1].firmware, "/opt/other");
  EXPECT_EQ(s.modules[1].params, (std::map<std::string, int32_t>{{"amp", 45}, {"control_ms", 10}, {"poll_ms", 500}}));
  EXPECT_EQ(s.modules[2].firmware, "fw-passive");
  EXPECT_EQ(s.modules[2].params, (std::map<std::string, int32_t>{{"control_ms", 20}, {"poll_ms", 500}}));
  // a letter chain takes them too
  const auto l = load_scene_text("programs: {rotation: {firmware: fw-nod}}\nchain: RP\n", "s.yaml");
  EXPECT_EQ(l.modules[0].firmware, "fw-nod");
  EXPECT_EQ(l.modules[1].firmware, "fw-passive");
}

TEST(Scene, ProgramsForAnUnknownTypeOrWithAnUnknownKeyAreNamed) {
  std::string e = scene_error_of("programs:\n  rotaton: {firmware: fw-x}\nchain: R\n");
  EXPECT_NE(e.find("s.yaml:2:3"), std::string::npos) << e;
  EXPECT_NE(e.find("'rotaton'"), std::string::npos) << e;
  e = scene_error_of("programs:\n  rotation: {firmwre: fw-x}\nchain: R\n");
  EXPECT_NE(e.find("s.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("firmwre"), std::string::npos) << e;
}

TEST(Scene, UnknownKeyIsNamedWithItsLineAndColumn) {
  const std::string e = scene_error_of("chain: RR\nphysics:\n  dt_us: 500\n  tik_us: 1000\n");
  EXPECT_NE(e.find("s.yaml:4:3"), std::string::npos) << e;
  EXPECT_NE(e.find("tik_us"), std::string::npos) << e;
  EXPECT_NE(e.find("tick_us"), std::string::npos) << e;  // the known keys are listed
}

TEST(Scene, UnknownChainLetterIsAnError) {
  EXPECT_EQ(scene_error_of("chain: RRX\n"),
            "s.yaml:1:8: 'chain' has unknown module letter 'X' (T touch, R rotation, H helicoidal, "
            "S support, E extension, W traveller, P passive)");
}

TEST(Scene, MissingChainIsAnError) {
  EXPECT_EQ(scene_error_of("name: x\n"),
            "s.yaml:1:1: missing key 'chain' (a string such as \"RRRRRRRR\" or a list of modules)");
}

TEST(Scene, NumberOfTheWrongTypeNamesTheKey) {
  const std::string e = scene_error_of("chain: R\nduration_s: long\n");
  EXPECT_EQ(e.rfind("s.yaml:2:13: 'scene.duration_s' ", 0), 0u) << e;
}

TEST(Scene, TickMustBeAMultipleOfThePhysicsStep) {
  EXPECT_EQ(scene_error_of("chain: R\nphysics: {dt_us: 400, tick_us: 1000}\n"),
            "s.yaml:2:10: 'physics.tick_us' (1000) must be a multiple of 'physics.dt_us' (400)");
  EXPECT_EQ(scene_error_of("chain: R\nphysics: {dt_us: 400, tick_us: 1200}\n"), "(no error)");
}

// a run is whole ticks: a tick longer than the run used to stretch it silently
TEST(Scene, TickLongerThanTheRunIsAnError) {
  EXPECT_EQ(scene_error_of("chain: R\nduration_s: 0.5\nphysics: {tick_us: 1000000}\n"),
            "s.yaml:3:20: 'physics.tick_us' (1000000 us) is longer than the run ('duration_s' 0.5 s)");
  EXPECT_EQ(scene_error_of("chain: R\nduration_s: 1\nphysics: {tick_us: 1000000}\n"), "(no error)");
}

TEST(Scene, OutOfRangeValueIsAnError) {
  const std::string e = scene_error_of("chain: R\nenvironment: {material: {bounce: 2}}\n");
  EXPECT_EQ(e.rfind("s.yaml:2:34: 'environment.material.bounce' = 2 ", 0), 0u) << e;
  EXPECT_EQ(scene_error_of("chain: R\nenvironment: {material: {bounce: 1}}\n"), "(no error)");
}

// ODE aborts on a non-finite position: the scene reader must stop it first
TEST(Scene, PlacementPositionIsFiniteAndBounded) {
  EXPECT_EQ(scene_error_of("chain: R\nplacement: {position_m: [0, .nan, 0.02]}\n"),
            "s.yaml:2:29: 'placement.position_m[1]' must be a finite number, not '.nan'");
  EXPECT_EQ(scene_error_of("chain: R\nplacement: {position_m: [-.inf, 0, 0.02]}\n"),
            "s.yaml:2:26: 'placement.position_m[0]' must be a finite number, not '-.inf'");
  EXPECT_EQ(scene_error_of("chain: R\nplacement: {position_m: [0, 0, 1e300]}\n"),
            "s.yaml:2:32: 'placement.position_m[2]' = 1e300 is out of range [-10000, 10000]");
  EXPECT_EQ(scene_error_of("chain: R\nplacement: {position_m: [1, 2, 0.1]}\n"), "(no error)");
}

TEST(Scene, DuplicateKeyAndSecondDocumentAreErrors) {
  EXPECT_EQ(scene_error_of("chain: R\nduration_s: 2\nduration_s: 5\n"),
            "s.yaml:3:1: duplicate key 'duration_s' (first at line 2, column 1)");
  EXPECT_EQ(scene_error_of("chain: R\n---\nchain: [\n").rfind("s.yaml:", 0), 0u);
  EXPECT_EQ(scene_error_of("chain: R\n---\nchain: S\n").rfind("s.yaml:3:1: a second YAML document", 0), 0u);
}

TEST(Scene, MalformedYamlGivesTheParserPosition) {
  const std::string e = scene_error_of("chain: R\nphysics: {dt_us: 500\n");
  EXPECT_EQ(e.rfind("s.yaml:", 0), 0u) << e;
  EXPECT_NE(e, "(no error)");
}

TEST(Scene, SolverIterationsAreAPhysicsSetting) {
  EXPECT_EQ(load_scene_text("chain: R\n", "s.yaml").world.solver_iterations, 30);
  EXPECT_EQ(load_scene_text("chain: R\nphysics: {solver_iterations: 200}\n", "s.yaml").world.solver_iterations, 200);
  const std::string e = scene_error_of("chain: R\nphysics: {solver_iterations: 0}\n");
  EXPECT_EQ(e.rfind("s.yaml:2:30: 'physics.solver_iterations' = 0 ", 0), 0u) << e;
}

TEST(Scene, TheSolverIsQuickStepUnlessTheSceneAsksForTheExactOne) {
  using Solver = chainsim::WorldConfig::Solver;
  EXPECT_EQ(load_scene_text("chain: R\n", "s.yaml").world.solver, Solver::QuickStep);
  EXPECT_EQ(load_scene_text("chain: R\nphysics: {solver: quickstep, solver_iterations: 50}\n", "s.yaml").world.solver,
            Solver::QuickStep);
  EXPECT_EQ(load_scene_text("chain: R\nphysics: {solver: exact}\n", "s.yaml").world.solver, Solver::Exact);
  const std::string bad = scene_error_of("chain: R\nphysics: {solver: lcp}\n");
  EXPECT_EQ(bad.rfind("s.yaml:2:19: 'physics.solver' 'lcp' is not known (known: quickstep, exact)", 0), 0u) << bad;
  // iterations mean nothing to the exact solver: said, not ignored
  const std::string both = scene_error_of("chain: R\nphysics: {solver: exact, solver_iterations: 50}\n");
  EXPECT_EQ(both.rfind("s.yaml:2:45: ", 0), 0u) << both;
  EXPECT_NE(both.find("'physics.solver_iterations' applies to the quickstep solver only"), std::string::npos) << both;
}
