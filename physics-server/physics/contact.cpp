// Contacts. See contact.h.
#include "physics/contact.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <tuple>

#include "environment/environment_geoms.h"
#include "model/units.h"

namespace chainsim {

Contacts::Contacts(dWorldID world, ContactMaterials materials)
    : world_(world), group_(dJointGroupCreate(0)), materials_(std::move(materials)) {}

Contacts::~Contacts() { dJointGroupDestroy(group_); }

int Contacts::add_body(dGeomID geom, int module) {
  const int index = static_cast<int>(body_module_.size());
  // 1-based body index; <= 0 marks the environment
  if (geom) dGeomSetData(geom, reinterpret_cast<void*>(static_cast<intptr_t>(index + 1)));
  body_module_.push_back(module);
  touched_.push_back(0);
  kept_.push_back(-1);
  return index;
}

void Contacts::keep_push(int body) {
  if (kept_[body] >= 0) return;
  kept_[body] = static_cast<int>(pushes_.size());
  pushes_.push_back(Eigen::Vector3d::Zero());
}

Eigen::Vector3d Contacts::push(int body) const {
  return kept_[body] >= 0 ? pushes_[kept_[body]] : Eigen::Vector3d::Zero();
}

void Contacts::warm_up(size_t n) {
  dContact dummy{};
  for (size_t k = 0; k < n; ++k) dJointCreateContact(world_, group_, &dummy);
  dJointGroupEmpty(group_);
}

void Contacts::collide(dSpaceID space) {
  std::fill(touched_.begin(), touched_.end(), 0);
  for (auto& p : pushes_) p.setZero();
  count_ = 0;
  deepest_ = Deepest{};
  dSpaceCollide(space, this, &Contacts::near_callback);
}

void Contacts::clear() { dJointGroupEmpty(group_); }

void Contacts::near_callback(void* data, dGeomID a, dGeomID b) {
  static_cast<Contacts*>(data)->collide_pair(a, b);
}

void Contacts::collide_pair(dGeomID a, dGeomID b) {
  const intptr_t ia = reinterpret_cast<intptr_t>(dGeomGetData(a));
  const intptr_t ib = reinterpret_cast<intptr_t>(dGeomGetData(b));
  if (ia <= 0 && ib <= 0) return;  // environment vs environment
  const intptr_t env_tag = ia <= 0 ? ia : ib;
  const Material* mat = env_tag < 0 ? &materials_.surface[EnvironmentGeoms::surface_index(env_tag)]
                                    : &materials_.ground;
  if (ia > 0 && ib > 0) {
    if (body_module_[ia - 1] == body_module_[ib - 1]) return;  // no self-collision
    if (dAreConnectedExcluding(dGeomGetBody(a), dGeomGetBody(b), dJointTypeContact)) return;  // docked
    mat = &materials_.module_module;
  }
  const int n = dCollide(a, b, kMaxContactsPerPair, buf_, sizeof(dContactGeom));
  if (n <= 0) return;
  if (ia > 0) touched_[ia - 1] = 1;
  if (ib > 0) touched_[ib - 1] = 1;
  for (auto [tag, geom, sign] : {std::tuple{ia, a, 1.0}, std::tuple{ib, b, -1.0}}) {
    if (tag <= 0 || kept_[tag - 1] < 0) continue;
    const dBodyID body = dGeomGetBody(geom);
    for (int k = 0; k < n; ++k) {
      // ODE's normal points into the first geom: it pushes a, and b the other way
      dVector3 v;
      dBodyVectorFromWorld(body, sign * buf_[k].normal[0], sign * buf_[k].normal[1], sign * buf_[k].normal[2], v);
      pushes_[kept_[tag - 1]] += (1.0 / n) * Eigen::Vector3d(v[0], v[1], v[2]);
    }
  }
  for (int k = 0; k < n; ++k) {
    if (buf_[k].depth > deepest_.depth_m) deepest_ = {buf_[k].depth, static_cast<int>((ia > 0 ? ia : ib) - 1)};
    dContact c;
    c.geom = buf_[k];
    c.surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
    c.surface.mu = mat->mu;
    c.surface.mu2 = 0;
    c.surface.rho = c.surface.rho2 = c.surface.rhoN = 0;
    c.surface.bounce = 0;
    c.surface.bounce_vel = 0;
    if (mat->bounce > 0) {
      c.surface.mode |= dContactBounce;
      c.surface.bounce = mat->bounce;
      c.surface.bounce_vel = 0.01;
    }
    c.surface.soft_erp = mat->soft_erp;
    c.surface.soft_cfm = mat->soft_cfm;
    c.surface.motion1 = c.surface.motion2 = c.surface.motionN = 0;
    c.surface.slip1 = c.surface.slip2 = 0;
    turn_friction_pyramid(c);
    dJointID j = dJointCreateContact(world_, group_, &c);
    dJointAttach(j, dGeomGetBody(c.geom.g1), dGeomGetBody(c.geom.g2));
    ++count_;
  }
}

// ODE's Coulomb friction is a pyramid: two directions in the contact
// plane, each limited to mu N, so something sliding at 45 degrees to them
// meets sqrt(2) times mu N. Left to ODE, the directions come from the normal
// alone (dPlaneSpace): on a floor the world's x and y, so a gait that slides
// sideways went elsewhere when the chain started at another heading (the
// lateral shift: 1.36 m across at 0 degrees, 0.96 m across and 0.86 m along
// at 45). Here the pyramid is turned about the normal so that one of its
// directions lies along the sliding velocity at the contact, which makes
// the friction against the motion exactly mu N, whatever the heading.
// Slow contacts keep ODE's own directions and the turn grows smoothly with
// the sliding speed (weight v^2 / (v^2 + kFrictionTurnSpeed^2)): turned
// sharply at mm/s speeds, a contact that a servo presses while it creeps
// chattered with QuickStep's 30 iterations (a touch cover read contact in
// 44 % of the steps instead of all of them; fine at 300 iterations).
void turn_friction_pyramid(dContact& c) {
  constexpr double kFrictionTurnSpeed = 0.01;  // m/s
  const dReal* n = c.geom.normal;
  dVector3 pp, qq;
  dPlaneSpace(n, pp, qq);
  const dBodyID b1 = dGeomGetBody(c.geom.g1), b2 = dGeomGetBody(c.geom.g2);
  dVector3 v1 = {0, 0, 0}, v2 = {0, 0, 0};
  if (b1) dBodyGetPointVel(b1, c.geom.pos[0], c.geom.pos[1], c.geom.pos[2], v1);
  if (b2) dBodyGetPointVel(b2, c.geom.pos[0], c.geom.pos[1], c.geom.pos[2], v2);
  const Eigen::Vector3d p(pp[0], pp[1], pp[2]), q(qq[0], qq[1], qq[2]);
  const Eigen::Vector3d v(v1[0] - v2[0], v1[1] - v2[1], v1[2] - v2[2]);
  const double vp = v.dot(p), vq = v.dot(q), s2 = vp * vp + vq * vq;
  // the smallest turn of (p, q) that puts p or q along the sliding, scaled
  // by the weight; a quarter turn maps the pyramid onto itself
  const double a = std::atan2(vq, vp);
  const double turn = (a - std::round(a / (kPi / 2)) * (kPi / 2)) *
                      (s2 / (s2 + kFrictionTurnSpeed * kFrictionTurnSpeed));
  // (Between the two ends the turn jumps from +w 45 to -w 45 degrees where
  // the sliding crosses a diagonal of the pyramid: no continuous blend of
  // "turn with the sliding" and "do not turn" exists on a quarter-turn
  // circle. The jump is 0 at both ends and largest, 45 degrees, at 1 cm/s.)
  Eigen::Vector3d d = std::cos(turn) * p + std::sin(turn) * q;
  d.normalize();  // p, q are unit for a unit normal; the pipe geoms write their own normals
  c.surface.mode |= dContactFDir1;
  c.fdir1[0] = d.x();
  c.fdir1[1] = d.y();
  c.fdir1[2] = d.z();
  c.fdir1[3] = 0;
}

}  // namespace chainsim
