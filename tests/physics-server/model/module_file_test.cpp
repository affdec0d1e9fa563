// Module definition files: what a file means, and errors that name
// file:line:column and the key at fault.
#include "model/module_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "model/module_def.h"
#include "model/units.h"

namespace chainsim {
namespace {


// a small valid module: a box body and a wheel on a hinge
const char* kGood = R"(type: cart
description: a box and a wheel
bodies:
  - {name: box, shape: box, size_m: [0.04, 0.02, 0.02], mass_kg: 0.008, position_m: [-0.02, 0, 0]}
  - name: wheel
    shape: cylinder
    radius_m: 0.005
    length_m: 0.002
    mass_kg: 0.001
    position_m: [-0.02, 0, -0.012]
    rotation: {axis: [1, 0, 0], angle_deg: 90}
joints:
  - {name: axle, type: hinge, parent: box, child: wheel, anchor_m: [-0.02, 0, -0.012], axis: [0, -1, 0], friction_nm_s_rad: 1e-6}
actuators:
  - {name: drive, type: servo, joint: axle, servo: {kt: 0.07}}
sensors:
  - {name: enc, type: wheel_encoder, joint: axle, channel: 0, counts_per_rev: 100}
  - {name: acc, type: accelerometer, body: box, channel: 2, range_g: 2, quaternion_wxyz: [0, 0, 0, 1]}
  - {name: current, type: motor_current, actuator: drive, channel: 1}
docking:
  front: {body: box}
  back: {body: box, position_m: [-0.04, 0, 0]}
)";

// text with the line at `line` (1-based) replaced
std::string with_line(const std::string& text, int line, const std::string& replacement) {
  size_t begin = 0;
  for (int l = 1; l < line; ++l) begin = text.find('\n', begin) + 1;
  const size_t end = text.find('\n', begin);
  return text.substr(0, begin) + replacement + text.substr(end);
}

std::string error_of(const std::string& text) {
  try {
    load_module_text(text, "m.yaml");
  } catch (const ModuleFileError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ModuleFile, ValidFileMapsOntoTheModuleDef) {
  const ModuleDef d = load_module_text(kGood, "m.yaml");
  EXPECT_EQ(d.type, "cart");
  EXPECT_EQ(d.description, "a box and a wheel");
  ASSERT_EQ(d.bodies.size(), 2u);
  EXPECT_EQ(d.bodies[0].shape, Shape::Box);
  EXPECT_EQ(d.bodies[0].box_m, Eigen::Vector3d(0.04, 0.02, 0.02));
  EXPECT_EQ(d.bodies[1].shape, Shape::Cylinder);
  // the wheel's axis (body z) turned onto -y
  EXPECT_LT(
      (d.bodies[1].pose.orientation * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0, -1, 0)).norm(),
      1e-12);
  ASSERT_EQ(d.joints.size(), 1u);
  EXPECT_EQ(d.joints[0].parent, 0);
  EXPECT_EQ(d.joints[0].child, 1);
  EXPECT_TRUE(std::isinf(d.joints[0].lo));
  EXPECT_DOUBLE_EQ(d.joints[0].friction_nm_s_rad, 1e-6);
  ASSERT_EQ(d.actuators.size(), 1u);
  ASSERT_TRUE(d.actuators[0].servo.has_value());
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->kt, 0.07);
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->km, ServoParams{}.km);  // the rest: Table 1
  ASSERT_EQ(d.sensors.size(), 3u);
  EXPECT_EQ(d.sensors[0].type, SensorType::WheelEncoder);
  EXPECT_EQ(d.sensors[0].counts_per_rev, 100);
  EXPECT_EQ(d.sensors[1].type, SensorType::Accelerometer);
  EXPECT_EQ(d.sensors[1].channel, 2);
  EXPECT_DOUBLE_EQ(d.sensors[1].range_g, 2.0);
  EXPECT_NEAR(std::fabs(d.sensors[1].orientation.z()), 1.0, 1e-12);
  EXPECT_EQ(d.sensors[2].actuator, 0);
  EXPECT_EQ(d.back.body, 0);
  EXPECT_DOUBLE_EQ(d.back.frame.position.x(), -0.04);
}

// the shipped files are the built-in types, each named after its file
TEST(ModuleFile, ServoCanSwitchOnCalibrationEffects) {
  std::string text = kGood;
  const std::string from = "servo: {kt: 0.07}";
  text.replace(text.find(from), from.size(), "servo: {backlash_deg: 2.5, pwm_frame_s: 0.02, coulomb_nm: 0.001}");
  const ModuleDef d = load_module_text(text, "m.yaml");
  ASSERT_TRUE(d.actuators[0].servo.has_value());
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->backlash_deg, 2.5);
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->pwm_frame_s, 0.02);
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->coulomb_nm, 0.001);
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->deadband_deg, 0.0);  // not named: off
}

// the effects' keys that only make sense together, or not together, and a
// pulse slope given in the report's us/deg where the file takes s/deg
TEST(ModuleFile, ServoEffectKeysThatDoNotGoTogetherAreNamed) {
  auto with_servo = [](const std::string& servo) {
    std::string text = kGood;
    const std::string from = "servo: {kt: 0.07}";
    text.replace(text.find(from), from.size(), "servo: " + servo);
    return text;
  };
  const std::string alone = error_of(with_servo("{pwm_pulse_s_per_deg: 1.1e-5}"));
  EXPECT_NE(alone.find("'pwm_pulse_s_per_deg' needs 'pwm_frame_s'"), std::string::npos) << alone;
  const std::string both = error_of(with_servo("{deadband_deg: 2, deadband_comparator_deg: 2}"));
  EXPECT_NE(both.find("'deadband_deg' and 'deadband_comparator_deg' are two forms of one deadband"),
            std::string::npos)
      << both;
  const std::string us = error_of(with_servo("{pwm_frame_s: 0.02, pwm_pulse_s_per_deg: 11.1}"));
  EXPECT_NE(us.find("pwm_pulse_s_per_deg"), std::string::npos) << us;
  const ModuleDef d = load_module_text(with_servo("{pwm_frame_s: 0.02, pwm_pulse_s_per_deg: 1.1e-5}"), "m.yaml");
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->pwm_pulse_s_per_deg, 1.1e-5);
  EXPECT_DOUBLE_EQ(d.actuators[0].servo->pwm_pulse_origin_deg, 90.0);  // the joint's 0 is the 1.5 ms centre
}

TEST(ModuleFile, ShippedFilesAreTheBuiltInTypes) {
  const std::vector<std::string> want = {"extension", "helicoidal", "passive",  "rotation",
                                         "support",   "touch",      "traveller"};
  EXPECT_EQ(builtin_module_names(), want);
  for (const std::string& name : want) {
    const ModuleDef from_file =
        load_module_file(std::string(CHAINSIM_SOURCE_DIR) + "/scenes/modules/" + name + ".yaml");
    const ModuleDef builtin = builtin_module_def(name);
    EXPECT_EQ(from_file.type, name);
    EXPECT_EQ(builtin.type, name);
    EXPECT_EQ(from_file.bodies.size(), builtin.bodies.size()) << name;
    EXPECT_EQ(module_mass_kg(from_file), module_mass_kg(builtin)) << name;
  }
  // the rotation module keeps the numbers of its former C++ definition
  const ModuleDef r = builtin_module_def("rotation");
  EXPECT_EQ(r.bodies[1].pose.position.x(), -0.023);
  EXPECT_EQ(r.joints[0].anchor_m.x(), -0.0165);
  EXPECT_NEAR(r.joints[1].hi, kPi / 2, 1e-15);
  EXPECT_LT(r.bodies[0].pose.orientation.angularDistance(
                Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()))),
            1e-15);
}

TEST(ModuleFile, UnknownKeyNamesFileLineColumnAndKey) {
  // line 8 of kGood is "    length_m: 0.002" (the wheel)
  const std::string e = error_of(with_line(kGood, 8, "    lenght_m: 0.002"));
  EXPECT_NE(e.find("m.yaml:8:5: unknown key 'lenght_m' in 'bodies[1]'"), std::string::npos) << e;
  EXPECT_NE(e.find("length_m"), std::string::npos) << e;  // lists the known keys
  const std::string top = error_of(std::string(kGood) + "colour: red\n");
  EXPECT_NE(top.find("m.yaml:23:1: unknown key 'colour' in 'module'"), std::string::npos) << top;
}

TEST(ModuleFile, BadShapeNamesFileLineColumn) {
  const std::string e = error_of(with_line(kGood, 6, "    shape: cone"));
  EXPECT_NE(e.find("m.yaml:6:12: 'bodies[1].shape' = 'cone' is not a shape (known: box, capsule, "
                   "cylinder, sphere)"),
            std::string::npos)
      << e;
  // a key of another shape
  const std::string r = error_of(with_line(kGood, 6, "    shape: sphere"));
  EXPECT_NE(r.find("m.yaml:8:5: 'bodies[1].length_m' does not apply to a sphere"),
            std::string::npos)
      << r;
  // a missing size
  const std::string m = error_of(with_line(kGood, 7, "    # no radius"));
  EXPECT_NE(m.find("m.yaml:5:5: 'bodies[1]' needs 'radius_m'"), std::string::npos) << m;
  // a size out of range
  const std::string n = error_of(with_line(kGood, 7, "    radius_m: -0.005"));
  EXPECT_NE(n.find("m.yaml:7:15: 'bodies[1].radius_m' = -0.005 is out of range"), std::string::npos)
      << n;
}

TEST(ModuleFile, JointReferencingAMissingBodyNamesItsLineAndTheBodies) {
  const std::string line =
      "  - {name: axle, type: hinge, parent: box, child: wheeel, anchor_m: [-0.02, 0, -0.012], "
      "axis: [0, -1, 0]}";
  const std::string e = error_of(with_line(kGood, 13, line));
  EXPECT_NE(e.find("m.yaml:13:51: 'joints[0].child': no body 'wheeel' in this module (bodies: box, "
                   "wheel)"),
            std::string::npos)
      << e;
}

TEST(ModuleFile, OtherErrorsArePlaced) {
  // an actuator on the wrong kind of joint
  std::string e = error_of(with_line(
      kGood, 15, "  - {name: drive, type: linear_servo, joint: axle, fmax_n: 1, l0_m: 0.01}"));
  EXPECT_NE(e.find("m.yaml:15:46: 'actuators[0].joint': a linear_servo needs a slider joint"),
            std::string::npos)
      << e;
  // two sensors on one ADC channel (the accelerometer takes 2, 3, 4)
  e = error_of(with_line(kGood, 19,
                         "  - {name: current, type: motor_current, actuator: drive, channel: 3}"));
  EXPECT_NE(
      e.find("m.yaml:1:1: module type 'cart': sensor 'current': ADC channel 3 is already used "
             "by sensor 'acc'"),
      std::string::npos)
      << e;
  // a duplicate name
  e = error_of(with_line(kGood, 5, "  - name: box"));
  EXPECT_NE(e.find("m.yaml:5:11: 'bodies[1].name': duplicate body name 'box'"), std::string::npos)
      << e;
  // a number that is not one
  e = error_of(with_line(kGood, 9, "    mass_kg: light"));
  EXPECT_NE(e.find("m.yaml:9:14: 'bodies[1].mass_kg' must be a number"), std::string::npos) << e;
  // hinge limits beyond a half turn
  e = error_of(with_line(kGood, 13,
                         "  - {name: axle, type: hinge, parent: box, child: wheel, anchor_m: [0, "
                         "0, 0], axis: [0, 1, 0], limits_deg: [-200, 0]}"));
  EXPECT_NE(e.find("m.yaml:13:"), std::string::npos) << e;
  EXPECT_NE(e.find("limits_deg"), std::string::npos) << e;
  // missing docking
  const std::string text = kGood;
  e = error_of(text.substr(0, text.find("docking:")));
  EXPECT_NE(e.find("m.yaml:1:1: missing key 'docking'"), std::string::npos) << e;
  // malformed YAML gives the parser's position
  e = error_of("type: x\nbodies: [\n");
  EXPECT_NE(e.find("m.yaml:"), std::string::npos) << e;
  // a file that is not there
  try {
    load_module_file("/nonexistent/m.yaml");
    FAIL();
  } catch (const ModuleFileError& x) {
    EXPECT_NE(std::string(x.what()).find("/nonexistent/m.yaml: cannot open"), std::string::npos);
  }
}

// a module type of n boxes in a row, each fixed to the one before it
std::string boxes(int n) {
  std::string t = "type: long\nbodies:\n";
  for (int i = 0; i < n; ++i)
    t += "  - {name: b" + std::to_string(i) + ", shape: box, size_m: [0.01, 0.01, 0.01], mass_kg: 0.01}\n";
  t += "joints:\n";
  for (int i = 1; i < n; ++i)
    t += "  - {name: j" + std::to_string(i) + ", type: fixed, parent: b" + std::to_string(i - 1) + ", child: b" +
         std::to_string(i) + "}\n";
  return t + "docking: {front: {body: b0}, back: {body: b0}}\n";
}

// a list as long as the module's bodies is counted before any entry is read,
// and refused naming the count and the bound
TEST(ModuleFile, ListsOverTheirBoundNameTheCountAndTheLimit) {
  EXPECT_EQ(error_of(boxes(32)), "(no error)");
  EXPECT_EQ(error_of(boxes(33)), "m.yaml:3:3: 'bodies' has 33 bodies, more than the limit of 32");
  // the other lists: ten thousand entries are refused at once
  std::string many;
  for (int i = 0; i < 10000; ++i) many += "  - {name: x" + std::to_string(i) + "}\n";
  const std::string one = boxes(1);
  const std::string bodies = one.substr(0, one.find("joints:"));  // lines 1-3
  const std::string dock = "docking: {front: {body: b0}, back: {body: b0}}\n";
  const std::vector<std::pair<std::string, std::string>> lists = {
      {"joints", "10000 joints, more than the limit of 32"},
      {"actuators", "10000 actuators, more than the limit of 16"},
      {"sensors", "10000 sensors, more than the limit of 32"},
      {"wheels", "10000 wheel sets, more than the limit of 8"},
      {"pads", "10000 pads, more than the limit of 8"},
  };
  for (const auto& [key, why] : lists)
    EXPECT_EQ(error_of(bodies + key + ":\n" + many + dock), "m.yaml:5:3: '" + key + "' has " + why);
}

// a body joined to nothing would fall away from its module: refused at the body
TEST(ModuleFile, EveryBodyIsJoinedToTheFirst) {
  const std::string three = boxes(3);
  const std::string no_joints = three.substr(0, three.find("joints:")) + "docking: {front: {body: b0}, back: {body: b0}}\n";
  const std::string why = "is not joined to 'b0' through 'joints': every body of a module must be (a fixed joint "
                          "where it does not move)";
  EXPECT_EQ(error_of(no_joints), "m.yaml:4:5: 'bodies[1]' ('b1') " + why);
  // b1 and b2 joined to each other, not to b0
  const std::string apart = three.substr(0, three.find("joints:")) +
                            "joints:\n  - {name: j, type: fixed, parent: b1, child: b2}\n"
                            "docking: {front: {body: b0}, back: {body: b0}}\n";
  EXPECT_EQ(error_of(apart), "m.yaml:4:5: 'bodies[1]' ('b1') " + why);
  // joined in any order of the list and of parent and child
  const std::string reversed = three.substr(0, three.find("joints:")) +
                               "joints:\n  - {name: j2, type: fixed, parent: b2, child: b1}\n"
                               "  - {name: j1, type: fixed, parent: b1, child: b0}\n"
                               "docking: {front: {body: b0}, back: {body: b0}}\n";
  EXPECT_EQ(error_of(reversed), "(no error)");
}

}  // namespace
}  // namespace chainsim
