// Spring-loaded wheels pressed against the environment's wall (DESIGN.md
// section 10, paper 6.6): a ring of `count` wheels around the module's x axis,
// each on an arm that a spring pushes outwards. The World realises each wheel
// as one contact per physics step between its body and the wall the arm meets
// (physics/wheels/wheel_contacts.h): a soft normal that is the spring, and
// friction only across the wheel (along its axle), so the wheel rolls freely
// along its rolling direction and grips up to mu times its own normal force
// across it.
//
// Geometry (module frame, as assembled): wheel k's arm pivots on the module's
// x axis at x_m and points along the radial direction at angle
// first_deg + k 360/count about x (0 = +y, 90 = +z). Its contact point is
// `reach` from the axis along that direction, between reach_min_m (arm
// folded) and reach_max_m (arm on its outer stop). The wheel meets the wall at
// the first point of the environment along the ray; farther than reach_max_m
// it is off the wall (no force). Normal force on the wall:
//   N = preload_n + stiffness_n_m (reach_max_m - reach) - damping (approach rate)
// Rolling direction: the circumferential direction (x cross radial) turned
// by helix_deg towards +x: 0 = rolls around the axis (a spinning head gives
// no thrust), 90 = rolls along the axis (a wheel that only resists rolling of
// the body, or a free-running odometer wheel). A head spinning at w about +x
// then advances at v = w r tan(helix) without slip (r = the contact's
// distance from the axis), and its motor torque tau becomes a thrust
// tau / (r tan(helix)).
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace chainsim {

struct WheelSetDef {
  std::string name;            // trace columns m<i>.<name><k>.n_N (normal force) and .f_N (across)
  int body = -1;               // the body carrying the arms (index)
  int count = 3;               // wheels, evenly spaced around the axis
  double first_deg = 90.0;     // angle of wheel 0 about x, from +y towards +z
  double x_m = 0.0;            // the arms' pivots on the module's x axis, module frame
  double helix_deg = 0.0;      // rolling direction from circumferential towards +x
  double reach_min_m = 0.0;    // contact point from the axis, arm folded
  double reach_max_m = 0.0;    // ... arm on its outer stop
  double preload_n = 0.0;      // normal force at reach_max_m
  double stiffness_n_m = 0.0;  // spring rate at the contact, > 0
  double damping_n_s_m = 0.0;  // along the normal, >= 0
  double mu = 0.0;             // friction across the wheel, >= 0
  // the tyre's cornering stiffness per newton of normal force, 1/rad: side
  // force = cornering N (slip angle) below mu N; 0 = rigid (no side creep)
  double cornering_per_rad = 0.0;
};

// A friction pad (the support module's arm tips): the pad at the end of an
// arm on `body`. Its face is `reach_m` from `position_m` along `direction`
// (module frame, as assembled; e.g. from the arm's hinge along the arm to its
// tip). It touches when the wall is nearer than that along the line; normal
// force = stiffness x the pad's compression along the wall's normal
// (+ damping), friction up to mu N in any direction along the wall. Whatever
// presses the pad (the arm's servo through its lever) sets N: the pad makes
// the contact one well-defined point with Coulomb friction.
struct PadDef {
  std::string name;            // trace columns m<i>.<name>.n_N, .f_N (friction magnitude)
  int body = -1;               // the arm
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();   // the line's origin, module frame
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();   // towards the pad, module frame
  double reach_m = 0.0;        // origin to the pad's face, > 0
  double stiffness_n_m = 0.0;  // > 0
  double damping_n_s_m = 0.0;  // >= 0
  double mu = 0.0;             // >= 0
};

// throw std::invalid_argument naming the wheel set or pad (body index, ranges)
void validate_wheel_set(const WheelSetDef& w, int n_bodies);
void validate_pad(const PadDef& p, int n_bodies);

}  // namespace chainsim
