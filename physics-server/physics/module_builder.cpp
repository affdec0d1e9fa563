// A module's bodies and joints in ODE. See module_builder.h.
#include "physics/module_builder.h"

#include <cmath>

namespace chainsim {

Eigen::Isometry3d to_isometry(const Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = p.orientation.normalized().toRotationMatrix();
  t.translation() = p.position;
  return t;
}

Eigen::Isometry3d body_isometry(dBodyID b) {
  const dReal* p = dBodyGetPosition(b);
  const dReal* q = dBodyGetQuaternion(b);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  t.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  return t;
}

namespace {

// the body of bd in world pose t, its mass and its geom
void create_body(dWorldID world, dSpaceID space, const BodyDef& bd, const Eigen::Isometry3d& t,
                 dBodyID* body, dGeomID* geom) {
  const Eigen::Quaterniond q(t.linear());
  dBodyID b = dBodyCreate(world);
  dBodySetPosition(b, t.translation().x(), t.translation().y(), t.translation().z());
  const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
  dBodySetQuaternion(b, dq);
  dMass m;
  dGeomID g = nullptr;
  switch (bd.shape) {
    case Shape::Capsule:
      dMassSetCapsuleTotal(&m, bd.mass_kg, 3, bd.radius_m, bd.length_m);
      g = dCreateCapsule(space, bd.radius_m, bd.length_m);
      break;
    case Shape::Cylinder:
      dMassSetCylinderTotal(&m, bd.mass_kg, 3, bd.radius_m, bd.length_m);
      g = dCreateCylinder(space, bd.radius_m, bd.length_m);
      break;
    case Shape::Box:
      dMassSetBoxTotal(&m, bd.mass_kg, bd.box_m.x(), bd.box_m.y(), bd.box_m.z());
      g = dCreateBox(space, bd.box_m.x(), bd.box_m.y(), bd.box_m.z());
      break;
    case Shape::Sphere:
      dMassSetSphereTotal(&m, bd.mass_kg, bd.radius_m);
      g = dCreateSphere(space, bd.radius_m);
      break;
  }
  dBodySetMass(b, &m);
  if (bd.collides) {
    dGeomSetBody(g, b);
  } else {  // the shape gave the mass; no contacts (e.g. a part inside another body)
    dGeomDestroy(g);
    g = nullptr;
  }
  *body = b;
  *geom = g;
}

dJointID create_joint(dWorldID world, const JointDef& jd, dBodyID child, dBodyID parent,
                      const Eigen::Isometry3d& frame) {
  const Eigen::Vector3d anchor = frame * jd.anchor_m;
  const Eigen::Vector3d axis = frame.linear() * jd.axis.normalized();
  dJointID j = nullptr;
  // body1 = child, body2 = parent: ODE's angle/position is body1 relative to body2
  switch (jd.type) {
    case JointType::Hinge:
      j = dJointCreateHinge(world, nullptr);
      dJointAttach(j, child, parent);
      dJointSetHingeAnchor(j, anchor.x(), anchor.y(), anchor.z());
      dJointSetHingeAxis(j, axis.x(), axis.y(), axis.z());
      if (std::isfinite(jd.lo)) dJointSetHingeParam(j, dParamLoStop, jd.lo);
      if (std::isfinite(jd.hi)) dJointSetHingeParam(j, dParamHiStop, jd.hi);
      break;
    case JointType::Slider:
      j = dJointCreateSlider(world, nullptr);
      dJointAttach(j, child, parent);
      dJointSetSliderAxis(j, axis.x(), axis.y(), axis.z());
      if (std::isfinite(jd.lo)) dJointSetSliderParam(j, dParamLoStop, jd.lo);
      if (std::isfinite(jd.hi)) dJointSetSliderParam(j, dParamHiStop, jd.hi);
      break;
    case JointType::Fixed:
      j = dJointCreateFixed(world, nullptr);
      dJointAttach(j, child, parent);
      dJointSetFixed(j);
      break;
  }
  return j;
}

}  // namespace

ModuleBodies build_module_bodies(dWorldID world, dSpaceID space, const ModuleDef& def,
                                 const Eigen::Isometry3d& frame) {
  ModuleBodies out;
  out.bodies.resize(def.bodies.size());
  out.geoms.resize(def.bodies.size());
  for (size_t b = 0; b < def.bodies.size(); ++b)
    create_body(world, space, def.bodies[b], frame * to_isometry(def.bodies[b].pose), &out.bodies[b],
                &out.geoms[b]);
  for (const JointDef& jd : def.joints)
    out.joints.push_back(create_joint(world, jd, out.bodies[jd.child], out.bodies[jd.parent], frame));
  return out;
}

}  // namespace chainsim
