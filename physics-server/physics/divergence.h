// Physics divergence: a body whose state is not finite, or moves faster,
// lies farther or sinks deeper into a wall than a chained modular robot can
// (a blow-up of the solver, e.g. a chain started inside the floor or tiny
// masses under big torques).
// Looked for after each tick by the run loop (cosim/lockstep_server.cpp).
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>

namespace chainsim {

class World;

// the documented bounds (docs/reliability.md); far above anything a shipped
// scene reaches, far below what a blown-up solver produces
struct DivergenceBounds {
  double max_speed_m_s = 10.0;           // body centre of mass
  double max_angular_speed_rad_s = 1000.0;
  double max_coordinate_m = 10000.0;     // as the scene's positions
  double max_penetration_m = 0.010;      // deepest contact into the environment or another module
};

struct Divergence {
  int module = -1;
  int body = -1;
  bool non_finite = false;  // NaN or infinity: the world cannot go on, whatever the mode
  std::string what;         // "module 3 (rotation) body 'shell': speed 70.2 m/s over the bound of 10 m/s"
};

// a body's velocity pointing down (gravity's -z) within 10 degrees of the
// vertical, as in a free fall off the end of a terrain or out of a pipe, not
// as a solver's blow-up flings it; a speed over the bound then says so
bool falling_straight_down(const Eigen::Vector3d& velocity);

// the first body (in module, body order) outside the bounds, if any
std::optional<Divergence> find_divergence(const World& world, const DivergenceBounds& bounds = {});

}  // namespace chainsim
