// Scene files: what loads, and errors that name file:line:column and the key.
#include <gtest/gtest.h>

#include <string>

#include "scene/scene.h"

using chainsim::load_scene_text;
using chainsim::SceneError;

namespace {
std::string error_of(const std::string& yaml) {
  try {
    load_scene_text(yaml, "s.yaml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(Scene, BuiltInDefaultIsASnakeOfEightRotationModules) {
  const auto s = chainsim::default_scene();
  ASSERT_EQ(s.modules.size(), 8u);
  for (const auto& m : s.modules) {
    EXPECT_EQ(m.type, "rotation");
    EXPECT_EQ(m.firmware, "fw-rotation");
  }
  EXPECT_EQ(s.world.chain.size(), 8u);
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

TEST(Scene, ExplicitModuleListCarriesFirmwareAndParams) {
  const auto s = load_scene_text(
      "chain:\n  - {type: rotation, params: {control_ms: 15}}\n  - {type: passive, firmware: /opt/fw}\n", "s.yaml");
  ASSERT_EQ(s.modules.size(), 2u);
  EXPECT_EQ(s.modules[0].params.at("control_ms"), 15);
  EXPECT_EQ(s.modules[1].firmware, "/opt/fw");
}

TEST(Scene, UnknownKeyIsNamedWithItsLineAndColumn) {
  const std::string e = error_of("chain: RR\nphysics:\n  dt_us: 500\n  tik_us: 1000\n");
  EXPECT_NE(e.find("s.yaml:4:3"), std::string::npos) << e;
  EXPECT_NE(e.find("tik_us"), std::string::npos) << e;
  EXPECT_NE(e.find("tick_us"), std::string::npos) << e;  // the known keys are listed
}

TEST(Scene, UnknownChainLetterIsAnError) {
  const std::string e = error_of("chain: RRX\n");
  EXPECT_NE(e.find("s.yaml:1:8"), std::string::npos) << e;
  EXPECT_NE(e.find("'X'"), std::string::npos) << e;
}

TEST(Scene, MissingChainIsAnError) {
  EXPECT_NE(error_of("name: x\n").find("missing key 'chain'"), std::string::npos);
}

TEST(Scene, NumberOfTheWrongTypeNamesTheKey) {
  const std::string e = error_of("chain: R\nduration_s: long\n");
  EXPECT_NE(e.find("s.yaml:2:13"), std::string::npos) << e;
  EXPECT_NE(e.find("duration_s"), std::string::npos) << e;
}

TEST(Scene, TickMustBeAMultipleOfThePhysicsStep) {
  const std::string e = error_of("chain: R\nphysics: {dt_us: 400, tick_us: 1000}\n");
  EXPECT_NE(e.find("multiple"), std::string::npos) << e;
}

TEST(Scene, OutOfRangeValueIsAnError) {
  const std::string e = error_of("chain: R\nenvironment: {material: {bounce: 2}}\n");
  EXPECT_NE(e.find("environment.material.bounce"), std::string::npos) << e;
}

TEST(Scene, MalformedYamlGivesTheParserPosition) {
  const std::string e = error_of("chain: R\nphysics: {dt_us: 500\n");
  EXPECT_EQ(e.rfind("s.yaml:", 0), 0u) << e;
  EXPECT_NE(e, "(no error)");
}

TEST(Scene, SolverIterationsAreAPhysicsSetting) {
  EXPECT_EQ(load_scene_text("chain: R\n", "s.yaml").world.solver_iterations, 30);
  EXPECT_EQ(load_scene_text("chain: R\nphysics: {solver_iterations: 200}\n", "s.yaml").world.solver_iterations, 200);
  const std::string e = error_of("chain: R\nphysics: {solver_iterations: 0}\n");
  EXPECT_NE(e.find("s.yaml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("solver_iterations"), std::string::npos) << e;
}
