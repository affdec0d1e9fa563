// The robot calibration's scenes: nominal values from the loaded scenes,
// the knobs that apply, and variants that load with the values changed.
#include "analysis/robot_calibration/scene_variants.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/module_def.h"

namespace chainsim {
namespace {

const std::string kScenes = std::string(CHAINSIM_SOURCE_DIR) + "/scenes/";

std::string temp_dir(const std::string& name) {
  const std::string d = testing::TempDir() + "/scene_variants_test_" + std::to_string(getpid()) + "_" + name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

const ActuatorDef& drive_motor(const ModuleDef& d) {
  for (const ActuatorDef& a : d.actuators)
    if (a.type == ActuatorType::DcMotor) return a;
  throw std::runtime_error("no DC motor");
}

TEST(SceneVariants, HelicoidalScenesDriveWheelsAndFriction) {
  const SceneVariants v(kScenes + "helicoidal-{slope}.yaml", {"0", "30"});
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v.nominal(robot_knob("drive_stall")), 8.930e-4);   // scenes/modules/helicoidal.yaml
  EXPECT_EQ(v.nominal(robot_knob("drive_free_speed")), 5.607);
  EXPECT_EQ(v.nominal(robot_knob("wheel_preload")), 0.2);
  EXPECT_EQ(v.nominal(robot_knob("wheel_friction")), 0.6);
  EXPECT_EQ(v.nominal(robot_knob("wall_friction")), 0.05);
  EXPECT_EQ(v.nominal(robot_knob("arm_grip_torque")), 0.0);
  EXPECT_EQ(v.usable(), (std::vector<int>{robot_knob("drive_stall"), robot_knob("drive_free_speed"),
                                          robot_knob("wheel_preload"), robot_knob("wheel_friction"),
                                          robot_knob("wall_friction")}));
  const std::string dir = temp_dir("heli");
  const std::string text = v.scene_text(
      1, {{robot_knob("drive_stall"), 1.5}, {robot_knob("wheel_friction"), 0.5}, {robot_knob("wall_friction"), 2.0}},
      dir);
  const Scene s = load_scene_text(text, dir + "/scene.yaml");
  EXPECT_DOUBLE_EQ(s.world.ground.mu, 0.1);
  const ModuleDef h = find_module_def(s.world.module_types, "helicoidal");
  const ActuatorDef& a = drive_motor(h);
  EXPECT_DOUBLE_EQ(a.fmax_n, 1.5 * 8.930e-4);
  EXPECT_DOUBLE_EQ(a.v_free_m_s, 5.607);
  ASSERT_EQ(h.wheels.size(), 2u);
  for (const WheelSetDef& w : h.wheels) {
    EXPECT_DOUBLE_EQ(w.mu, 0.3) << w.name;
    EXPECT_DOUBLE_EQ(w.preload_n, 0.2) << w.name;
  }
  EXPECT_EQ(s.world.environment.pipe.segments[0].slope_deg, 30.0);  // the row's own scene
  // no knobs: the scene as it is, with the built-in module type
  const Scene s0 = load_scene_text(v.scene_text(0, {}, dir), dir + "/scene.yaml");
  EXPECT_TRUE(s0.world.module_types.empty());
  EXPECT_EQ(s0.world.ground.mu, 0.05);
  std::filesystem::remove_all(dir);
}

TEST(SceneVariants, InchwormScenesArmGripScalesEveryArmServo) {
  const SceneVariants v(kScenes + "inchworm-{slope}.yaml", {"0", "30"});
  const int grip = robot_knob("arm_grip_torque");
  EXPECT_EQ(v.nominal(grip), 0.14);  // the driven arm servo's kt
  EXPECT_EQ(v.nominal(robot_knob("drive_stall")), 0.0);
  EXPECT_NE(std::find(v.usable().begin(), v.usable().end(), grip), v.usable().end());
  const std::string dir = temp_dir("inch");
  const Scene s = load_scene_text(v.scene_text(0, {{grip, 0.5}}, dir), dir + "/scene.yaml");
  const ModuleDef d = find_module_def(s.world.module_types, "support");
  std::vector<double> kt;
  for (const ActuatorDef& a : d.actuators)
    if (a.type == ActuatorType::Servo) kt.push_back(a.servo ? a.servo->kt : -1);
  EXPECT_EQ(kt, (std::vector<double>{0.07, 0.035, 0.035}));
  std::filesystem::remove_all(dir);
}

TEST(SceneVariants, InchwormScenesExtensionForceScalesTheLinearServo) {
  const SceneVariants v(kScenes + "inchworm-{slope}.yaml", {"0", "90"});
  const int force = robot_knob("extension_force");
  EXPECT_EQ(v.nominal(force), 0.356);  // scenes/modules/extension.yaml (fitted on Table 3)
  EXPECT_NE(std::find(v.usable().begin(), v.usable().end(), force), v.usable().end());
  const std::string dir = temp_dir("inch-ext");
  const Scene s = load_scene_text(v.scene_text(1, {{force, 2.0}}, dir), dir + "/scene.yaml");
  const ModuleDef d = find_module_def(s.world.module_types, "extension");
  std::vector<double> fmax;
  for (const ActuatorDef& a : d.actuators)
    if (a.type == ActuatorType::LinearServo) fmax.push_back(a.fmax_n);
  EXPECT_EQ(fmax, std::vector<double>{0.712});
  // the rest of the scene stays: the slope's row, the exact solver
  EXPECT_EQ(s.world.solver, WorldConfig::Solver::Exact);
  EXPECT_EQ(s.world.environment.pipe.segments.at(0).slope_deg, 90);
  // a helicoidal scene has no extension: the knob does not apply
  const SceneVariants h(kScenes + "helicoidal-{slope}.yaml", {"0"});
  EXPECT_EQ(std::find(h.usable().begin(), h.usable().end(), force), h.usable().end());
  std::filesystem::remove_all(dir);
}

TEST(SceneVariants, MissingOrBrokenScenesAreNamed) {
  try {
    SceneVariants(kScenes + "helicoidal-{slope}.yaml", {"0", "45"});
    FAIL() << "no error";
  } catch (const RobotError& e) {
    EXPECT_NE(std::string(e.what()).find("helicoidal-45.yaml: no such scene"), std::string::npos) << e.what();
  }
  const std::string dir = temp_dir("bad");
  std::ofstream(dir + "/s-1.yaml") << "chain: H\nphysics: {dt_us: -5}\n";
  try {
    SceneVariants(dir + "/s-{slope}.yaml", {"1"});
    FAIL() << "no error";
  } catch (const RobotError& e) {
    EXPECT_NE(std::string(e.what()).find("s-1.yaml:2:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(row 1)"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace chainsim
