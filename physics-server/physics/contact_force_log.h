// Diagnostics: the forces the ordinary contacts (geom collisions) put on each
// body in the last step, read back from ODE (dJointFeedback). Off unless
// WorldConfig::log_contact_forces: it costs a feedback record per contact.
// The records come from a pool made at assembly; contacts beyond it are not
// logged (counted in dropped()), so a step never allocates.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>

#include <vector>

namespace chainsim {

class ContactForceLog {
 public:
  struct Sum {
    double normal_n = 0;                                // sum of normal force magnitudes, N
    Eigen::Vector3d force = Eigen::Vector3d::Zero();    // total contact force, world, N
    int contacts = 0;
  };
  void init(int bodies, int capacity);
  bool enabled() const { return !pool_.empty(); }
  void begin_step();
  // a contact joint just created between body indices a and b (-1 =
  // environment), normal pointing into a
  void add(dJointID j, int a, int b, const dReal* normal);
  void end_step();
  const Sum& body(int index) const { return sums_[index]; }
  int dropped() const { return dropped_; }

 private:
  struct Rec {
    int a = -1, b = -1;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
  };
  std::vector<dJointFeedback> pool_;
  std::vector<Rec> recs_;
  std::vector<Sum> sums_;
  int used_ = 0, dropped_ = 0;
};

}  // namespace chainsim
