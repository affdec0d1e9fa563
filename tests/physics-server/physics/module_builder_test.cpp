// Rigid groups: parts joined rigidly (a module's fixed joints, the docks
// between modules) are one ODE body with the parts' combined mass and their
// geoms at offsets; no fixed joint is left. Parts still report their own
// poses, velocities and masses.
#include <gtest/gtest.h>

#include <ode/ode.h>

#include <Eigen/Geometry>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/module_def.h"
#include "physics/module_builder.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {

// an ODE world and space of their own, destroyed with the test
struct OdeScope {
  OdeScope() {
    dInitODE2(0);
    dAllocateODEDataForThread(dAllocateMaskAll);
    world = dWorldCreate();
    space = dSimpleSpaceCreate(nullptr);
  }
  ~OdeScope() {
    dSpaceDestroy(space);
    dWorldDestroy(world);
  }
  dWorldID world;
  dSpaceID space;
};

// module frames of a straight chain along -x, each module's front face at the
// previous one's back face
std::vector<Eigen::Isometry3d> straight_frames(const std::vector<ModuleDef>& defs) {
  std::vector<Eigen::Isometry3d> frames;
  Eigen::Isometry3d face = Eigen::Isometry3d::Identity();
  for (const ModuleDef& d : defs) {
    frames.push_back(face * to_isometry(d.front.frame).inverse());
    face = frames.back() * to_isometry(d.back.frame);
  }
  return frames;
}

// inertia of a solid part about point `about` of its group frame (parallel axes)
Eigen::Matrix3d inertia_about(const BodyDef& bd, const Eigen::Isometry3d& part_in_group,
                              const Eigen::Vector3d& about) {
  const Eigen::Matrix3d r = part_in_group.linear();
  const Eigen::Vector3d d = part_in_group.translation() - about;
  return r * body_inertia_kg_m2(bd) * r.transpose() +
         bd.mass_kg * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

TEST(RigidGroups, DockedRingsAreOneBodyWithTheirCombinedMass) {
  OdeScope ode;
  const std::vector<ModuleDef> defs = {builtin_module_def("rotation"), builtin_module_def("rotation")};
  const std::vector<Eigen::Isometry3d> frames = straight_frames(defs);
  const std::vector<ModuleBodies> parts = build_chain_bodies(ode.world, ode.space, defs, frames);
  ASSERT_EQ(parts.size(), 2u);
  // module 0's back ring (part 2) and module 1's front ring (part 0) share a body
  const dBodyID dock = parts[0].bodies[2];
  EXPECT_EQ(parts[1].bodies[0], dock);
  std::set<dBodyID> distinct;
  for (const ModuleBodies& m : parts) distinct.insert(m.bodies.begin(), m.bodies.end());
  EXPECT_EQ(distinct.size(), 5u);  // 6 parts, one pair joined

  dMass m;
  dBodyGetMass(dock, &m);
  EXPECT_NEAR(m.mass, 2 * defs[0].bodies[2].mass_kg, 1e-15);
  EXPECT_NEAR(Eigen::Vector3d(m.c[0], m.c[1], m.c[2]).norm(), 0.0, 0.0);  // centre at the body's origin
  // the body sits at the two rings' common centre, halfway between them
  const Eigen::Vector3d a = (frames[0] * to_isometry(defs[0].bodies[2].pose)).translation();
  const Eigen::Vector3d b = (frames[1] * to_isometry(defs[1].bodies[0].pose)).translation();
  const Eigen::Isometry3d body = body_isometry(dock);
  EXPECT_LT((body.translation() - (a + b) / 2).norm(), 1e-15);
  // its inertia is the sum of the rings' about that centre (parallel axes)
  const Eigen::Matrix3d expect = inertia_about(defs[0].bodies[2], parts[0].offsets[2], Eigen::Vector3d::Zero()) +
                                 inertia_about(defs[1].bodies[0], parts[1].offsets[0], Eigen::Vector3d::Zero());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.I[r * 4 + c], expect(r, c), 1e-15) << r << "," << c;
  // each ring's offset puts it where it was placed
  EXPECT_LT(((body * parts[0].offsets[2]).translation() - a).norm(), 1e-15);
  EXPECT_LT(((body * parts[1].offsets[0]).translation() - b).norm(), 1e-15);
  // each ring's geom sits at its part's place
  const dReal* g = dGeomGetPosition(parts[1].geoms[0]);
  EXPECT_LT((Eigen::Vector3d(g[0], g[1], g[2]) - b).norm(), 1e-15);

  // no fixed joint anywhere: each body's joints are the two hinges of a module
  for (dBodyID id : distinct)
    for (int j = 0; j < dBodyGetNumJoints(id); ++j)
      EXPECT_NE(dJointGetType(dBodyGetJoint(id, j)), dJointTypeFixed);
  EXPECT_EQ(dBodyGetNumJoints(dock), 2);  // module 0's yaw, module 1's pitch
}

TEST(RigidGroups, AFixedJointInsideAModuleJoinsItsParts) {
  OdeScope ode;
  const std::vector<ModuleDef> defs = {builtin_module_def("touch")};
  const std::vector<ModuleBodies> parts = build_chain_bodies(ode.world, ode.space, defs, straight_frames(defs));
  ASSERT_EQ(parts[0].bodies.size(), 2u);
  EXPECT_EQ(parts[0].bodies[0], parts[0].bodies[1]);  // cover on its base
  ASSERT_EQ(parts[0].joints.size(), 1u);
  EXPECT_EQ(parts[0].joints[0], nullptr);             // no ODE joint for it
  dMass m;
  dBodyGetMass(parts[0].bodies[0], &m);
  EXPECT_NEAR(m.mass, module_mass_kg(defs[0]), 1e-15);
}

TEST(RigidGroups, AHingeBetweenRigidlyJoinedPartsIsRefusedNamingIt) {
  OdeScope ode;
  ModuleDef d = builtin_module_def("rotation");
  JointDef weld;
  weld.name = "weld";
  weld.type = JointType::Fixed;
  weld.parent = 0;  // front ring
  weld.child = 1;   // capsule, which the pitch hinge joins to the front ring
  d.joints.push_back(weld);
  const std::vector<ModuleDef> defs = {d};
  try {
    build_chain_bodies(ode.world, ode.space, defs, straight_frames(defs));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'pitch'"), std::string::npos) << e.what();
  }
}

TEST(StartClear, ABodyStartingInsideTheEnvironmentIsRefusedNamingIt) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);  // on the floor: accepted
  EXPECT_NO_THROW(world_of(c, {"rotation", "rotation"}));
  c.head_position.z() = 0.008;  // the rings (12.5 mm) 4.5 mm into the floor
  try {
    World w = world_of(c, {"rotation", "rotation"});
    FAIL() << "no exception";
  } catch (const WorldSetupError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("module 0 (rotation) body 'front' starts 4.5 mm inside the environment"), std::string::npos) << m;
  }
}

TEST(RigidGroups, PartsOfAChainReportTheirOwnPosesMassesAndVelocities) {
  WorldConfig c;
  c.gravity_m_s2 = 0;
  World w = world_of(c, {"rotation", "rotation", "rotation"});
  const std::vector<ModuleDef> defs(3, builtin_module_def("rotation"));
  Eigen::Isometry3d face = Eigen::Isometry3d::Identity();
  face.translation() = c.head_position;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Isometry3d frame = face * to_isometry(defs[k].front.frame).inverse();
    for (int b = 0; b < 3; ++b) {
      const World::BodyState s = w.body_state(k, b);
      const Eigen::Isometry3d placed = frame * to_isometry(defs[k].bodies[b].pose);
      EXPECT_LT((s.position - placed.translation()).norm(), 1e-12) << k << " " << b;
      const Eigen::Quaterniond q(s.quaternion_wxyz[0], s.quaternion_wxyz[1], s.quaternion_wxyz[2],
                                 s.quaternion_wxyz[3]);
      EXPECT_LT(q.angularDistance(Eigen::Quaterniond(placed.linear())), 1e-12) << k << " " << b;
      EXPECT_NEAR(s.mass_kg, defs[k].bodies[b].mass_kg, 1e-15);
    }
    face = frame * to_isometry(defs[k].back.frame);
  }
  EXPECT_LT(w.max_docking_error_m(), 1e-12);
  // spun about z, a shared ring's point moves as a point of the rigid body: v = w x r
  w.add_body_torque(1, 0, Eigen::Vector3d(0, 0, 1e-4));
  w.step();
  const World::BodyState ring = w.body_state(1, 0), back = w.body_state(0, 2);
  EXPECT_LT((ring.angular_velocity - back.angular_velocity).norm(), 1e-15);  // one body
  EXPECT_GT(ring.angular_velocity.norm(), 0.0);
  // the two rings' centres are 5 mm apart along the chain, so their speeds differ by w x 5 mm
  const Eigen::Vector3d dv = ring.linear_velocity - back.linear_velocity;
  const Eigen::Vector3d expect = ring.angular_velocity.cross(ring.position - back.position);
  EXPECT_LT((dv - expect).norm(), 1e-12);
  EXPECT_GT(dv.norm(), 0.0);
}

}  // namespace
}  // namespace chainsim
