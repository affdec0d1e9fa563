// A chain's parts and joints in ODE. See module_builder.h.
#include "physics/module_builder.h"

#include "physics/world.h"

#include <cmath>
#include <numeric>
#include <stdexcept>

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

dMass part_mass(const BodyDef& bd) {
  dMass m;
  switch (bd.shape) {
    case Shape::Capsule: dMassSetCapsuleTotal(&m, bd.mass_kg, 3, bd.radius_m, bd.length_m); break;
    case Shape::Cylinder: dMassSetCylinderTotal(&m, bd.mass_kg, 3, bd.radius_m, bd.length_m); break;
    case Shape::Box: dMassSetBoxTotal(&m, bd.mass_kg, bd.box_m.x(), bd.box_m.y(), bd.box_m.z()); break;
    case Shape::Sphere: dMassSetSphereTotal(&m, bd.mass_kg, bd.radius_m); break;
  }
  return m;
}

namespace {

dGeomID create_geom(dSpaceID space, const BodyDef& bd) {
  switch (bd.shape) {
    case Shape::Capsule: return dCreateCapsule(space, bd.radius_m, bd.length_m);
    case Shape::Cylinder: return dCreateCylinder(space, bd.radius_m, bd.length_m);
    case Shape::Box: return dCreateBox(space, bd.box_m.x(), bd.box_m.y(), bd.box_m.z());
    case Shape::Sphere: return dCreateSphere(space, bd.radius_m);
  }
  return nullptr;
}

void to_ode(const Eigen::Matrix3d& r, dMatrix3 out) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out[i * 4 + j] = r(i, j);
    out[i * 4 + 3] = 0;
  }
}

void set_body_pose(dBodyID b, const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.linear());
  dBodySetPosition(b, t.translation().x(), t.translation().y(), t.translation().z());
  const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
  dBodySetQuaternion(b, dq);
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
      break;  // its parts share one body
  }
  return j;
}

// rigid groups of the chain's parts, numbered by their first part: the
// group of every part (parts numbered module by module, in def order)
class RigidGroups {
 public:
  explicit RigidGroups(size_t n) : root_(n) { std::iota(root_.begin(), root_.end(), 0); }
  void join(size_t a, size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) root_[std::max(a, b)] = std::min(a, b);  // the smaller index stays the root
  }
  size_t find(size_t a) {
    while (root_[a] != a) a = root_[a] = root_[root_[a]];
    return a;
  }

 private:
  std::vector<size_t> root_;
};

}  // namespace

std::vector<ModuleBodies> build_chain_bodies(dWorldID world, dSpaceID space,
                                             const std::vector<ModuleDef>& defs,
                                             const std::vector<Eigen::Isometry3d>& frames,
                                             bool share_docks) {
  // every part, numbered module by module
  std::vector<size_t> first(defs.size() + 1, 0);
  for (size_t k = 0; k < defs.size(); ++k) first[k + 1] = first[k] + defs[k].bodies.size();
  const size_t n = first.back();
  std::vector<Eigen::Isometry3d> pose(n);
  std::vector<const BodyDef*> def_of(n);
  for (size_t k = 0; k < defs.size(); ++k)
    for (size_t b = 0; b < defs[k].bodies.size(); ++b) {
      pose[first[k] + b] = frames[k] * to_isometry(defs[k].bodies[b].pose);
      def_of[first[k] + b] = &defs[k].bodies[b];
    }

  RigidGroups groups(n);
  for (size_t k = 0; k < defs.size(); ++k) {
    for (const JointDef& jd : defs[k].joints)
      if (jd.type == JointType::Fixed) groups.join(first[k] + jd.child, first[k] + jd.parent);
    if (share_docks && k + 1 < defs.size())
      groups.join(first[k] + defs[k].back.body, first[k + 1] + defs[k + 1].front.body);
  }

  // one ODE body per group, created in the order of the groups' first parts
  std::vector<dBodyID> body(n, nullptr);
  std::vector<Eigen::Isometry3d> offset(n, Eigen::Isometry3d::Identity());
  std::vector<char> shared(n, 0);  // the part shares its body with others
  for (size_t root = 0; root < n; ++root) {
    if (groups.find(root) != root) continue;
    std::vector<size_t> members;
    for (size_t p = root; p < n; ++p)
      if (groups.find(p) == root) members.push_back(p);
    const dBodyID b = dBodyCreate(world);
    if (members.size() == 1) {  // a body of its own, exactly as placed
      set_body_pose(b, pose[root]);
      const dMass m = part_mass(*def_of[root]);
      dBodySetMass(b, &m);
      body[root] = b;
      continue;
    }
    // the group's frame: the first part's orientation about the common centre of mass
    double total = 0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();
    for (size_t p : members) {
      total += def_of[p]->mass_kg;
      com += def_of[p]->mass_kg * pose[p].translation();
    }
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
    frame.linear() = pose[root].linear();
    frame.translation() = com / total;
    dMass sum;
    dMassSetZero(&sum);
    for (size_t p : members) {
      offset[p] = frame.inverse() * pose[p];
      dMass m = part_mass(*def_of[p]);
      dMatrix3 r;
      to_ode(offset[p].linear(), r);
      dMassRotate(&m, r);
      dMassTranslate(&m, offset[p].translation().x(), offset[p].translation().y(),
                     offset[p].translation().z());
      dMassAdd(&sum, &m);
      body[p] = b;
      shared[p] = 1;
    }
    dMassTranslate(&sum, -sum.c[0], -sum.c[1], -sum.c[2]);  // ODE wants the centre at the origin
    sum.c[0] = sum.c[1] = sum.c[2] = 0;
    set_body_pose(b, frame);
    dBodySetMass(b, &sum);
  }

  std::vector<ModuleBodies> out(defs.size());
  for (size_t k = 0; k < defs.size(); ++k) {
    const ModuleDef& def = defs[k];
    ModuleBodies& mb = out[k];
    for (size_t b = 0; b < def.bodies.size(); ++b) {
      const size_t p = first[k] + b;
      mb.bodies.push_back(body[p]);
      mb.offsets.push_back(offset[p]);
      dGeomID g = nullptr;
      if (def.bodies[b].collides) {
        g = create_geom(space, def.bodies[b]);
        dGeomSetBody(g, body[p]);
        if (shared[p]) {
          dMatrix3 r;
          to_ode(offset[p].linear(), r);
          dGeomSetOffsetRotation(g, r);
          dGeomSetOffsetPosition(g, offset[p].translation().x(), offset[p].translation().y(),
                                 offset[p].translation().z());
        }
      }
      mb.geoms.push_back(g);
    }
    for (const JointDef& jd : def.joints) {
      if (jd.type != JointType::Fixed && mb.bodies[jd.child] == mb.bodies[jd.parent])
        throw WorldSetupError("module " + std::to_string(k) + " (" + def.type + "): joint '" +
                                    jd.name + "' joins two parts that are already rigidly joined");
      mb.joints.push_back(create_joint(world, jd, mb.bodies[jd.child], mb.bodies[jd.parent], frames[k]));
    }
  }
  return out;
}

}  // namespace chainsim
