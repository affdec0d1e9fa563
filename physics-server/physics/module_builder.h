// The rigid parts of one module in ODE: its bodies (with their collision
// geoms) and the joints between them, built from its ModuleDef with the
// module frame at a given pose. Actuators, sensors and docking are the
// World's (world.cpp).
#pragma once

#include <ode/ode.h>

#include <Eigen/Geometry>
#include <vector>

#include "model/module_def.h"

namespace chainsim {

struct ModuleBodies {
  std::vector<dBodyID> bodies;  // in def.bodies order
  std::vector<dGeomID> geoms;   // bodies[b]'s geom, in space; nullptr: it does not collide
  std::vector<dJointID> joints; // in def.joints order; body1 = child, body2 = parent
};

// creates def's bodies and joints; frame = module frame -> world
ModuleBodies build_module_bodies(dWorldID world, dSpaceID space, const ModuleDef& def,
                                 const Eigen::Isometry3d& frame);

// a Pose as a transform
Eigen::Isometry3d to_isometry(const Pose& p);
// a body's frame -> world, now
Eigen::Isometry3d body_isometry(dBodyID b);

}  // namespace chainsim
