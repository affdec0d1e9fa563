// The rigid parts of a chain's modules in ODE, and the joints between them,
// built from their ModuleDefs with each module frame at a given pose.
//
// Parts joined rigidly (a fixed joint inside a module, such as the touch
// module's cover on its base, and the dock between a module's back face and
// the next module's front face) become ONE ODE body: its mass is the parts'
// combined mass about their common centre, each part's collision geom sits
// at its offset in it, and no fixed joint is left for the solver (a fixed
// joint is 6 constraint rows that QuickStep only nearly satisfies). A part
// alone in its group is a body of its own exactly as placed. Everything that
// speaks of a part (poses in traces, sensors, wheels, forces) goes through
// its offset in the shared body.
//
// Actuators, sensors and wheels are the World's (world.cpp).
#pragma once

#include <ode/ode.h>

#include <Eigen/Geometry>
#include <vector>

#include "model/module_def.h"

namespace chainsim {

struct ModuleBodies {
  std::vector<dBodyID> bodies;            // the ODE body of each part (def.bodies order); shared within a rigid group
  std::vector<Eigen::Isometry3d> offsets; // each part's frame in its ODE body's frame (identity for a lone part)
  std::vector<dGeomID> geoms;             // each part's geom, in space; nullptr: it does not collide
  std::vector<dJointID> joints;           // def.joints order; nullptr for a fixed joint (its parts share a body)
};

// creates the parts and joints of a chain: module k is defs[k] with its
// module frame at frames[k] (module frame -> world); module k's back face is
// docked to module k + 1's front face: the two parts share one body, or, with
// share_docks false, keep their own (the caller joins them). Throws
// std::invalid_argument naming the joint when a hinge or slider would join two
// parts of one rigid group.
std::vector<ModuleBodies> build_chain_bodies(dWorldID world, dSpaceID space,
                                             const std::vector<ModuleDef>& defs,
                                             const std::vector<Eigen::Isometry3d>& frames,
                                             bool share_docks = true);

// a part's own mass in its own frame (centre at its origin), as ODE computes it
dMass part_mass(const BodyDef& bd);

// a Pose as a transform
Eigen::Isometry3d to_isometry(const Pose& p);
// a body's frame -> world, now
Eigen::Isometry3d body_isometry(dBodyID b);

}  // namespace chainsim
