// Wheel contacts. See wheel_contacts.h.
#include "physics/wheels/wheel_contacts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "model/units.h"
#include "physics/module_builder.h"

namespace chainsim {
namespace {

constexpr double kPadFilterS = 0.005;  // low-pass of a pad's normal force for its grip bound

Eigen::Vector3d to_world(dBodyID b, const Eigen::Vector3d& v) {
  dVector3 w;
  dBodyVectorToWorld(b, v.x(), v.y(), v.z(), w);
  return Eigen::Vector3d(w[0], w[1], w[2]);
}

}  // namespace

WheelContacts::WheelContacts(dWorldID world, const WallProbe* probe, double h,
                             double surface_layer)
    : world_(world), group_(dJointGroupCreate(0)), probe_(probe), h_(h), layer_(surface_layer),
      pad_filter_(1.0 - std::exp(-h / kPadFilterS)), module_first_(1, 0) {}

WheelContacts::~WheelContacts() { dJointGroupDestroy(group_); }

void WheelContacts::warm_up() {
  dContact dummy{};
  for (size_t k = 0; k < wheels_.size(); ++k) dJointCreateContact(world_, group_, &dummy);
  dJointGroupEmpty(group_);
}

void WheelContacts::add_module(int module, const std::vector<WheelSetDef>& sets,
                               const std::vector<PadDef>& pads,
                               const std::vector<dBodyID>& bodies,
                               const Eigen::Isometry3d& frame) {
  if (module + 1 != static_cast<int>(module_first_.size()))
    throw std::logic_error("WheelContacts::add_module: modules out of order");
  for (const WheelSetDef& s : sets) {
    const dBodyID body = bodies.at(s.body);
    const Eigen::Isometry3d to_body = body_isometry(body).inverse();
    const Eigen::Vector3d axis_w = frame.linear() * Eigen::Vector3d::UnitX();
    const double helix = deg_to_rad(s.helix_deg);
    for (int k = 0; k < s.count; ++k) {
      const double phi = deg_to_rad(s.first_deg + 360.0 * k / s.count);
      const Eigen::Vector3d radial_w =
          frame.linear() * Eigen::Vector3d(0, std::cos(phi), std::sin(phi));
      const Eigen::Vector3d circ_w = axis_w.cross(radial_w);
      // the axle: perpendicular to the rolling direction cos(helix) circ + sin(helix) axis
      const Eigen::Vector3d axle_w = std::cos(helix) * axis_w - std::sin(helix) * circ_w;
      Wheel w;
      w.module = module;
      w.name = s.name + std::to_string(k);
      w.body = body;
      w.pivot_b = to_body * (frame * Eigen::Vector3d(s.x_m, 0, 0));
      w.radial_b = to_body.linear() * radial_w;
      w.axle_b = to_body.linear() * axle_w;
      w.reach_min = s.reach_min_m;
      w.reach_max = s.reach_max_m;
      w.preload = s.preload_n;
      w.k = s.stiffness_n_m;
      w.mu = s.mu;
      w.cornering = s.cornering_per_rad;
      // the spring-damper as a soft constraint (ODE manual, "soft constraint")
      w.erp = h_ * s.stiffness_n_m / (h_ * s.stiffness_n_m + s.damping_n_s_m);
      w.cfm = 1.0 / (h_ * s.stiffness_n_m + s.damping_n_s_m);
      wheels_.push_back(w);
    }
  }
  for (const PadDef& d : pads) {
    const dBodyID body = bodies.at(d.body);
    const Eigen::Isometry3d to_body = body_isometry(body).inverse();
    Wheel w;
    w.module = module;
    w.name = d.name;
    w.body = body;
    w.pad = true;
    w.pivot_b = to_body * (frame * d.position_m);
    w.radial_b = to_body.linear() * (frame.linear() * d.direction.normalized());
    w.axle_b = Eigen::Vector3d::Zero();
    w.reach_min = 0;
    w.reach_max = d.reach_m;
    w.k = d.stiffness_n_m;
    w.mu = d.mu;
    w.erp = h_ * d.stiffness_n_m / (h_ * d.stiffness_n_m + d.damping_n_s_m);
    w.cfm = 1.0 / (h_ * d.stiffness_n_m + d.damping_n_s_m);
    wheels_.push_back(w);
  }
  module_first_.push_back(static_cast<int>(wheels_.size()));
}

// A pad's face is the end of its line, p + reach u. Cast from p, the wall
// within reach; the depth is the face's distance beyond it along the normal.
// Against the analytic pipe, three cases the cast alone does not see right:
//  * the face past an open end (no piece owns it) touches nothing, wherever
//    the line met the wall before the end: a pad hanging out of the pipe
//    pressed on the wall from there, the contact acting near the pad's
//    origin while the depth was the face's, and the arm, pushed at the
//    wrong point, opened further;
//  * a face that has been past an open end touches nothing until it is
//    back in the bore: come back into the pipe's length beyond the bore's
//    radius, it is outside the pipe (the pipe's end face, which is not
//    modelled, would stop it there), not suddenly deep in the wall.
//    Without these two, a support sliding out of a vertical pipe diverges;
//  * the origin in the wall (an arm's hinge beyond the bore while its
//    module lies on the wall: arms have no collision shape): no cast from
//    there; the face, if it is in the wall too, presses from the wall point
//    nearest to it. Letting go there instead would make the pad press at
//    once from as deep as its face had gone when its origin came back into
//    the bore.
bool WheelContacts::pad_on_wall(Wheel& w, const Eigen::Vector3d& p, const Eigen::Vector3d& u, WallHit* hit,
                                double* depth) const {
  const Eigen::Vector3d face = p + w.reach_max * u;
  WallHit at_face;
  int piece = w.hint;   // the cast's hint stays its own
  const double face_gap = probe_->pipe_wall_gap(face, &piece, &at_face);
  const bool past_end = face_gap == -std::numeric_limits<double>::infinity();
  if (past_end) {
    w.face_outside = probe_->has_pipe();
  } else if (face_gap < 0) {
    w.face_outside = false;
  }
  if (probe_->cast(p, u, w.reach_max, &w.hint, hit)) {
    if (hit->pipe && w.face_outside) return false;
    *depth = (w.reach_max - hit->t) * std::max(0.05, -u.dot(hit->normal));
    return true;
  }
  WallHit at_origin;
  if (w.face_outside || !(face_gap > 0) || !(probe_->pipe_wall_gap(p, &w.hint, &at_origin) > 0)) return false;
  *hit = at_face;
  *depth = face_gap;
  hit->t = 0;
  return true;
}

int WheelContacts::begin_step() {
  int made = 0;
  for (Wheel& w : wheels_) {
    w.st_prev_on = w.st.on;
    w.st.on = false;
    const Eigen::Vector3d p = body_isometry(w.body) * w.pivot_b;
    const Eigen::Vector3d u = to_world(w.body, w.radial_b);
    WallHit hit;
    if (!probe_) continue;
    double pad_depth = 0;   // a pad's: how far its face lies beyond the wall
    if (w.pad) {
      if (!pad_on_wall(w, p, u, &hit, &pad_depth)) continue;
    } else if (!probe_->cast(p, u, w.reach_max, &w.hint, &hit)) {
      continue;
    }
    const Eigen::Vector3d& n = hit.normal;
    Eigen::Vector3d across;
    if (w.pad) {  // along the sliding velocity (any direction when at rest)
      dVector3 v;
      dBodyGetPointVel(w.body, hit.point.x(), hit.point.y(), hit.point.z(), v);
      across = Eigen::Vector3d(v[0], v[1], v[2]);
      across -= across.dot(n) * n;
      if (across.norm() < 1e-6) {
        dVector3 pp, qq;
        const dVector3 nn = {n.x(), n.y(), n.z(), 0};
        dPlaneSpace(nn, pp, qq);
        across = Eigen::Vector3d(pp[0], pp[1], pp[2]);
      }
    } else {
      across = to_world(w.body, w.axle_b);
    }
    across -= across.dot(n) * n;
    const double len = across.norm();
    dContact c{};
    for (int i = 0; i < 3; ++i) {
      c.geom.pos[i] = hit.point[i];
      c.geom.normal[i] = n[i];  // into the free space: moving the body along it separates
    }
    // ODE subtracts the surface layer from the depth; the force at rest is k * depth
    c.geom.depth = w.pad ? pad_depth + layer_
                         : (w.reach_max - hit.t) + w.preload / w.k + layer_;
    c.surface.mode = dContactSoftERP | dContactSoftCFM | dContactMu2;
    c.surface.soft_erp = w.erp;
    c.surface.soft_cfm = w.cfm;
    c.surface.mu = 0;
    c.surface.mu2 = 0;
    if (w.pad) {
      // Coulomb friction in any direction along the wall (fdir1 along the
      // sliding), bounded by mu times the pad's normal force low-passed over
      // the steps before (not dContactApprox1's iterated normal: pressed by
      // a light servo-driven arm that did not converge in 30 iterations)
      across = len > 1e-6 ? Eigen::Vector3d(across / len) : Eigen::Vector3d::Zero();
      if (w.mu > 0 && len > 1e-6) {
        c.surface.mode |= dContactFDir1;
        for (int i = 0; i < 3; ++i) c.fdir1[i] = across[i];
        c.surface.mu = c.surface.mu2 = w.mu * std::max(0.0, w.n_filtered);
      }
    } else if (len > 1e-6 && w.mu > 0) {
      across /= len;
      c.surface.mode |= dContactApprox1 | dContactFDir1;
      c.surface.mu = w.mu;
      for (int i = 0; i < 3; ++i) c.fdir1[i] = across[i];
      if (w.cornering > 0) {
        // a tyre's side force F = C alpha, alpha = v_across / v_rolling: a
        // slip velocity v_across = F v_rolling / C, C = cornering N (spring law)
        dVector3 v;
        dBodyGetPointVel(w.body, hit.point.x(), hit.point.y(), hit.point.z(), v);
        const Eigen::Vector3d vw(v[0], v[1], v[2]);
        const Eigen::Vector3d roll = n.cross(across);
        const double n_spring = w.preload + w.k * (w.reach_max - hit.t);
        c.surface.mode |= dContactSlip1;
        c.surface.slip1 = std::fabs(vw.dot(roll)) / (w.cornering * std::max(n_spring, 1e-3));
      }
    } else {
      across.setZero();
    }
    dJointID j = dJointCreateContact(world_, group_, &c);
    dJointAttach(j, w.body, nullptr);
    w.fb = dJointFeedback{};
    dJointSetFeedback(j, &w.fb);
    w.st.on = true;
    w.st.reach_m = hit.t;
    w.st.point = hit.point;
    w.normal = n;
    w.across = across;
    ++made;
  }
  made_ = made;
  return made;
}

void WheelContacts::end_step() {
  for (Wheel& w : wheels_) {
    if (!w.st.on) {
      w.st.normal_n = w.st.across_n = 0;
      w.n_filtered = 0;  // a pad leaving the wall lets go at once
      continue;
    }
    const Eigen::Vector3d f(w.fb.f1[0], w.fb.f1[1], w.fb.f1[2]);
    w.st.normal_n = f.dot(w.normal);
    if (w.pad) {
      w.st.across_n = (f - w.st.normal_n * w.normal).norm();
      w.n_filtered += (std::max(0.0, w.st.normal_n) - w.n_filtered) * pad_filter_;
    } else {
      w.st.across_n = f.dot(w.across);
    }
  }
  dJointGroupEmpty(group_);
}

const WheelContacts::Wheel* WheelContacts::first(int module, int* n) const {
  if (module < 0 || module + 1 >= static_cast<int>(module_first_.size()))
    throw std::out_of_range("module index " + std::to_string(module) + " out of range");
  *n = module_first_[module + 1] - module_first_[module];
  return wheels_.data() + module_first_[module];
}

int WheelContacts::count(int module) const {
  int n = 0;
  first(module, &n);
  return n;
}

const WheelContacts::State& WheelContacts::state(int module, int wheel) const {
  int n = 0;
  const Wheel* w = first(module, &n);
  if (wheel < 0 || wheel >= n)
    throw std::out_of_range("wheel " + std::to_string(wheel) + " of module " +
                            std::to_string(module) + " out of range");
  return w[wheel].st;
}

const std::string& WheelContacts::name(int module, int wheel) const {
  int n = 0;
  const Wheel* w = first(module, &n);
  if (wheel < 0 || wheel >= n) throw std::out_of_range("wheel out of range");
  return w[wheel].name;
}

void WheelContacts::append_header(int module, const std::string& prefix, std::string* out) const {
  int n = 0;
  const Wheel* w = first(module, &n);
  for (int i = 0; i < n; ++i)
    *out += "," + prefix + w[i].name + ".n_N," + prefix + w[i].name + ".f_N";
}

void WheelContacts::append_row(int module, std::string* out) const {
  int n = 0;
  const Wheel* w = first(module, &n);
  char buf[48];
  for (int i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof buf, ",%.4f,%.4f", w[i].st.normal_n, w[i].st.across_n);
    *out += buf;
  }
}

}  // namespace chainsim
