// How to build a World: physics step, seed, where the chain starts, the
// environment, materials, the servo model, the solver, the docks and the
// scene's own module types. Plain data, apart from World (world.h), so that a
// Scene holds one without the ODE world's interface.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <vector>

#include "environment/environment.h"
#include "environment/material.h"
#include "model/module_def.h"
#include "model/servo_params.h"

namespace chainsim {

// how to build a World; read once by its constructor, never changed by it
struct WorldConfig {
  int64_t dt_us = 500;                 // physics step
  uint64_t seed = 1;                   // seeds ODE's dRandSetSeed and the sensor noise
  Eigen::Vector3d head_position{0, 0, 0.02};  // centre of the head's front face, m
  double heading_rad = 0.0;            // the chain points along +x rotated by this about z
  double roll_rad = 0.0;               // then turned by this about its own axis (either way of placing it)
  // if set, overrides heading_rad: the head's front-face frame (module frame)
  // -> world; the chain is laid along its -x (e.g. along a pipe's axis)
  std::optional<Eigen::Quaterniond> head_orientation;
  Material ground;                     // module-environment contact (pairs not in environment.contacts)
  // module-module contact (plastic on plastic), unless environment.contacts has (module, module)
  Material module_contact{0.3, 0.0, 0.2, 1e-5};
  EnvironmentConfig environment;       // plane, terrain, pipe or mesh (environment.h)
  ServoParams servo;                   // every servo's model (paper Table 1 defaults)
  double gravity_m_s2 = 9.81;
  int solver_iterations = 30;          // ODE QuickStep iterations (see world.cpp for the measurements)
  // the constraint solver: ODE's iterative QuickStep (solver_iterations), or
  // its exact LCP solver dWorldStep (iterations do not apply), whose cost
  // grows with the cube of a connected group's constraint rows: for short
  // chains whose results depend on the iterations (world.cpp)
  enum class Solver { QuickStep, Exact };
  Solver solver = Solver::QuickStep;
  // The docks (module k's back face on module k + 1's front face). Unset
  // (the default): the docked parts share one ODE body, rigid and with no
  // joint (module_builder.h). Set: each dock is a joint between the two
  // parts' own bodies, whose force and moment are measured (World::dock_force):
  // a ball joint at the faces' centre (as stiff as the solver makes a joint)
  // and an angular motor whose stops let the faces turn play_deg each way
  // about each axis, then hold them with the stops' stiffness and damping
  // (0: as stiff as the solver makes a joint; else ERP = h k / (h k + c),
  // CFM = 1 / (h k + c)). The real docks' play and the compliance of their
  // plastic: docs/scene-reference.md, physics.dock.
  struct DockConfig {
    double play_deg = 0;  // as the scene gives it (an exact round trip)
    double stiffness_nm_per_rad = 0;
    double damping_nm_s_per_rad = 0;
  };
  std::optional<DockConfig> dock;
  // module types the chain may name besides the built-ins (looked up first:
  // test fixtures, a scene's own types)
  std::vector<ModuleDef> module_types;
};

}  // namespace chainsim
