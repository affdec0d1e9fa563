// Contact force log. See contact_force_log.h.
#include "physics/contact_force_log.h"

#include <cmath>

namespace chainsim {

void ContactForceLog::init(int bodies, int capacity) {
  pool_.assign(capacity, dJointFeedback{});
  recs_.assign(capacity, Rec{});
  sums_.assign(bodies, Sum{});
}

void ContactForceLog::begin_step() {
  used_ = 0;
  dropped_ = 0;
}

void ContactForceLog::add(dJointID j, int a, int b, const dReal* normal) {
  if (used_ >= static_cast<int>(pool_.size())) {
    if (!pool_.empty()) ++dropped_;
    return;
  }
  pool_[used_] = dJointFeedback{};
  dJointSetFeedback(j, &pool_[used_]);
  recs_[used_] = Rec{a, b, Eigen::Vector3d(normal[0], normal[1], normal[2])};
  ++used_;
}

void ContactForceLog::end_step() {
  for (Sum& s : sums_) s = Sum{};
  for (int i = 0; i < used_; ++i) {
    const Rec& r = recs_[i];
    const Eigen::Vector3d f1(pool_[i].f1[0], pool_[i].f1[1], pool_[i].f1[2]);
    const Eigen::Vector3d f2(pool_[i].f2[0], pool_[i].f2[1], pool_[i].f2[2]);
    if (r.a >= 0) {
      sums_[r.a].force += f1;
      sums_[r.a].normal_n += std::fabs(f1.dot(r.n));
      ++sums_[r.a].contacts;
    }
    if (r.b >= 0) {
      sums_[r.b].force += f2;
      sums_[r.b].normal_n += std::fabs(f2.dot(r.n));
      ++sums_[r.b].contacts;
    }
  }
}

}  // namespace chainsim
