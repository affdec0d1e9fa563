// Module types as data: the built-ins, validation, masses and inertias as
// defined, chain assembly (docking faces meet, heading, head position).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>
#include <string>

#include "model/module_def.h"
#include "model/units.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {


TEST(ModuleLibrary, BuiltinsAreValid) {
  for (const std::string& name : builtin_module_names()) {
    const ModuleDef d = builtin_module_def(name);
    EXPECT_EQ(d.type, name);
    EXPECT_NO_THROW(validate_module_def(d)) << name;
  }
}

TEST(ModuleLibrary, UnknownTypeListsKnownTypes) {
  try {
    builtin_module_def("wormhole");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("wormhole"), std::string::npos) << msg;
    EXPECT_NE(msg.find("rotation"), std::string::npos) << msg;
    EXPECT_NE(msg.find("passive"), std::string::npos) << msg;
  }
  EXPECT_THROW(world_of(WorldConfig{}, {"rotation", "wormhole"}), std::invalid_argument);
}

TEST(ModuleLibrary, RotationModuleIsTheDescribedOne) {
  const ModuleDef d = builtin_module_def("rotation");
  ASSERT_EQ(d.bodies.size(), 3u);
  EXPECT_EQ(d.bodies[0].shape, Shape::Cylinder);
  EXPECT_EQ(d.bodies[1].shape, Shape::Capsule);
  EXPECT_EQ(d.bodies[2].shape, Shape::Cylinder);
  EXPECT_NEAR(module_mass_kg(d), 0.010, 1e-12);
  EXPECT_NEAR(2 * d.bodies[0].radius_m, 0.025, 1e-12);
  ASSERT_EQ(d.joints.size(), 2u);
  EXPECT_EQ(d.joints[0].name, "pitch");
  EXPECT_EQ(d.joints[1].name, "yaw");
  EXPECT_NEAR(d.joints[0].hi, kPi / 2, 1e-12);
  EXPECT_NEAR(d.joints[0].lo, -kPi / 2, 1e-12);
  EXPECT_EQ(driven_servo_actuators(d).size(), 2u);
  EXPECT_NEAR(module_mass_kg(builtin_module_def("passive")), 0.010, 1e-12);
}

TEST(ModuleLibrary, ValidationRejectsBrokenDefs) {
  ModuleDef d = builtin_module_def("rotation");
  d.joints[0].child = 7;
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  d = builtin_module_def("rotation");
  d.bodies[1].mass_kg = 0;
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  d = builtin_module_def("rotation");
  d.actuators[0].joint = -1;
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  d = builtin_module_def("rotation");
  d.bodies[2].name = d.bodies[0].name;
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
}

TEST(ModuleLibrary, AnalyticInertias) {
  BodyDef b;
  b.mass_kg = 2.0;
  b.radius_m = 0.1;
  b.shape = Shape::Sphere;
  EXPECT_NEAR(body_inertia_kg_m2(b)(0, 0), 0.4 * 2 * 0.01, 1e-12);
  b.shape = Shape::Cylinder;
  b.length_m = 0.3;
  EXPECT_NEAR(body_inertia_kg_m2(b)(2, 2), 0.5 * 2 * 0.01, 1e-12);
  EXPECT_NEAR(body_inertia_kg_m2(b)(0, 0), 2 * (3 * 0.01 + 0.09) / 12, 1e-12);
  b.shape = Shape::Capsule;
  b.length_m = 0.0;  // a capsule without straight part is a sphere
  EXPECT_NEAR(body_inertia_kg_m2(b)(0, 0), 0.4 * 2 * 0.01, 1e-12);
  EXPECT_NEAR(body_inertia_kg_m2(b)(2, 2), 0.4 * 2 * 0.01, 1e-12);
  b.shape = Shape::Box;
  b.box_m = Eigen::Vector3d(0.1, 0.2, 0.3);
  EXPECT_NEAR(body_inertia_kg_m2(b)(0, 0), 2 * (0.04 + 0.09) / 12, 1e-12);
}

// the bodies ODE simulates have the masses and inertias of the definition
TEST(ModuleLibrary, WorldBodiesHaveTheDefinedMassAndInertia) {
  World w = world_of(WorldConfig{}, {"rotation", "passive", "rotation"});
  ASSERT_EQ(w.module_count(), 3);
  for (int m = 0; m < w.module_count(); ++m) {
    const ModuleDef d = builtin_module_def(w.module_type(m));
    ASSERT_EQ(w.body_count(m), static_cast<int>(d.bodies.size()));
    double total = 0;
    for (int b = 0; b < w.body_count(m); ++b) {
      const World::BodyState s = w.body_state(m, b);
      EXPECT_EQ(w.body_name(m, b), d.bodies[b].name);
      EXPECT_NEAR(s.mass_kg, d.bodies[b].mass_kg, 1e-15);
      const Eigen::Matrix3d expect = body_inertia_kg_m2(d.bodies[b]);
      EXPECT_LT((s.inertia_kg_m2 - expect).cwiseAbs().maxCoeff(), 1e-6 * expect.maxCoeff())
          << w.module_type(m) << "." << d.bodies[b].name << "\nODE:\n"
          << s.inertia_kg_m2 << "\ndefined:\n" << expect;
      total += s.mass_kg;
    }
    EXPECT_NEAR(total, 0.010, 1e-12);
  }
  EXPECT_EQ(w.servo_count(0), 2);
  EXPECT_EQ(w.servo_count(1), 0);
}

// head's front face at head_position, every back face on the next front face,
// chain along +x rotated by the heading
TEST(ModuleLibrary, ChainAssembledHeadFirstAlongHeading) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0.1, -0.2, 0.5);
  c.heading_rad = 0.7;
  c.gravity_m_s2 = 0;
  World w = world_of(c, {"rotation", "rotation", "passive", "rotation"});
  EXPECT_LT(w.max_docking_error_m(), 1e-12);
  const ModuleDef rot = builtin_module_def("rotation");
  // front connector of the head: its centre is half its thickness behind the face
  const Eigen::Vector3d dir(std::cos(0.7), std::sin(0.7), 0);
  const Eigen::Vector3d expect = c.head_position - dir * (rot.bodies[0].length_m / 2);
  EXPECT_LT((w.body_state(0, 0).position - expect).norm(), 1e-12);
  // the tail trails along -dir: the chain's centre of mass lies behind the head
  const Eigen::Vector3d com = w.chain_com();
  EXPECT_LT((com - c.head_position).dot(dir), -0.05);
  EXPECT_NEAR((com - c.head_position).cross(dir).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace chainsim
