// Contacts: which geoms touch in a step, with what material, and how ODE's
// friction is set up for them. The near callback of dSpaceCollide lives here.
//
// Geom user data tells the parties apart: a module body's geom holds
// 1 + its body index (add_body), an environment geom its surface tag (<= 0,
// EnvironmentGeoms::surface_tag). Pairs within one module and docked pairs
// never collide; environment geoms never collide with each other.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>

#include <vector>

#include "environment/material.h"

namespace chainsim {

// the contact parameters of a world, resolved once when it is built
struct ContactMaterials {
  std::vector<Material> surface;  // environment surface index -> its contact with a module
  Material ground;                // an environment geom with no surface (tag 0) and a module
  Material module_module;         // two modules
};

class Contacts {
 public:
  static constexpr int kMaxContactsPerPair = 8;

  Contacts(dWorldID world, ContactMaterials materials);
  ~Contacts();
  Contacts(const Contacts&) = delete;
  Contacts& operator=(const Contacts&) = delete;

  // a module body's geom (nullptr: a body that does not collide); returns
  // its body index (0, 1, ... in call order)
  int add_body(dGeomID geom, int module);
  // fill the contact group once with n joints and empty it: the group keeps
  // its arenas, so later steps do not allocate for up to n contacts
  void warm_up(size_t n);

  // this step's contact joints for every touching pair in space, in the order
  // the space reports them; resets and sets the touch flags
  void collide(dSpaceID space);
  // after the step: the contact joints go
  void clear();

  bool touched(int body) const { return touched_[body] != 0; }  // had a contact in the last step

  // sum the pushes on a body (one that a sectored touch sensor reads)
  void keep_push(int body);
  // the last step's pushes on a body kept with keep_push, in the frame of
  // its ODE body: the sum over the geoms it touched of each one's push, the
  // mean of its contacts' unit normals as they push the body (a pair's
  // contacts are one push however finely the collider samples it); zero
  // for a body not kept
  Eigen::Vector3d push(int body) const;
  int count() const { return count_; }                            // contact joints of the last step
  // the deepest contact of the last step (depth 0, body -1: none): how far
  // a body went into the environment or another module
  struct Deepest {
    double depth_m = 0;
    int body = -1;
  };
  const Deepest& deepest() const { return deepest_; }
  int module_of(int body) const { return body_module_[body]; }

 private:
  static void near_callback(void* data, dGeomID a, dGeomID b);
  void collide_pair(dGeomID a, dGeomID b);

  dWorldID world_;
  dJointGroupID group_ = nullptr;
  const ContactMaterials materials_;
  std::vector<int> body_module_;          // body index -> module
  std::vector<unsigned char> touched_;    // body index -> touched in the last step
  std::vector<int> kept_;                 // body index -> index into pushes_, -1: not kept
  std::vector<Eigen::Vector3d> pushes_;
  int count_ = 0;
  Deepest deepest_;
  dContactGeom buf_[kMaxContactsPerPair];
};

// ODE's friction pyramid turned about the contact normal so that one of its
// directions lies along the sliding at the contact (sets fdir1); see contact.cpp
void turn_friction_pyramid(dContact& c);

}  // namespace chainsim
