// The wheels of the modules' wheel sets (model/wheel_def.h) as ODE contacts,
// rebuilt every physics step.
//
// Per wheel and step: the arm's ray from its pivot along its radial
// direction (both fixed in the body) is cast against the environment
// (environment/pipe_wall_probe.h). No wall within reach_max_m: the wheel is
// off the wall and nothing is created. Else one contact joint between the
// wheel's body and the static environment at the wall point:
//  * normal = the wall's normal; soft ERP/CFM from the spring and damper
//    (ODE's manual: ERP = h k / (h k + c), CFM = 1 / (h k + c)) and a depth
//    of (reach_max - reach) + preload / k (+ ODE's surface layer, which it
//    subtracts), so that the normal force is the arm's spring law
//    preload + k (reach_max - reach) - c (approach rate), never pulling;
//  * friction on one direction only, fdir1 = the wheel's axle direction
//    projected into the wall's tangent plane, mu = the wheel's, mu2 = 0 (free
//    rolling), dContactApprox1: each wheel grips up to mu times its own
//    normal force.
// A contact joint's force is read back (dJointFeedback) after the step: the
// normal force and the force across the wheel (along fdir1) on the body.
// Pads (arm tips): the line from the pad's origin to its face is cast;
// within reach, one soft contact on the pad's body whose normal force is
// whatever presses the pad, and Coulomb friction in any direction along the
// wall bounded by mu times that normal force (low-passed over 5 ms); across_n
// is then the friction's magnitude. Against an analytic pipe, a pad's face
// past an open end touches nothing (nor after, until it is back in the
// bore), and a pad whose origin is in the wall presses from the wall point
// nearest to its face (pad_on_wall).
// Wheel contacts are not collisions: they set no touch sensor.
// No allocation in a step (the feedback records are made at assembly).
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "environment/pipe_wall_probe.h"
#include "model/wheel_def.h"

namespace chainsim {

class WheelContacts {
 public:
  struct State {
    bool on = false;          // touched the wall in the last step
    double reach_m = 0;       // contact point from the axis (on) 
    double normal_n = 0;      // normal force of the last step, N (0 = off)
    double across_n = 0;      // friction force across the wheel on the body, N (signed; pad: magnitude)
    Eigen::Vector3d point = Eigen::Vector3d::Zero();   // wall point (on), world
  };

  // h: the physics step, s; surface_layer: dWorldSetContactSurfaceLayer's.
  // The contacts go into a joint group of their own.
  WheelContacts(dWorldID world, const WallProbe* probe, double h, double surface_layer);
  ~WheelContacts();
  WheelContacts(const WheelContacts&) = delete;
  WheelContacts& operator=(const WheelContacts&) = delete;
  // the wheel sets of module `module`; bodies = the module's bodies by index
  // (as placed); module_frame: module frame -> world at assembly
  void add_module(int module, const std::vector<WheelSetDef>& sets,
                  const std::vector<PadDef>& pads, const std::vector<dBodyID>& bodies,
                  const Eigen::Isometry3d& module_frame);

  // after the last add_module: fill the joint group once with a joint per
  // wheel and empty it (it keeps its arenas: steps do not allocate)
  void warm_up();
  // before the world steps (dWorldQuickStep or dWorldStep): contact joints
  // for the wheels on the wall; returns how many
  int begin_step();
  // after the world stepped: the forces; the contact joints go
  void end_step();
  int on_count() const { return made_; }  // wheels and pads on the wall in the last step

  int count(int module) const;
  const State& state(int module, int wheel) const;
  const std::string& name(int module, int wheel) const;

  // trace: ",<prefix><name>.n_N,<prefix><name>.f_N" per wheel of the module
  void append_header(int module, const std::string& prefix, std::string* out) const;
  void append_row(int module, std::string* out) const;

 private:
  struct Wheel {
    int module = -1;
    std::string name;         // set name + index
    dBodyID body = nullptr;
    Eigen::Vector3d pivot_b, radial_b, axle_b;  // body frame
    double reach_min = 0, reach_max = 0, preload = 0, k = 0, mu = 0, cornering = 0;
    double erp = 0, cfm = 0;
    bool pad = false;         // friction in every direction along the wall
    bool st_prev_on = false;  // on the wall in the step before
    double n_filtered = 0;    // pad: normal force, low-passed
    int hint = -1;            // pipe piece of the last hit
    bool face_outside = false;  // pad: its face has been past an open end and not back in the bore since
    State st;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero(), across = Eigen::Vector3d::Zero();
    dJointFeedback fb{};
  };
  const Wheel* first(int module, int* n) const;
  // a pad (origin p, direction u, world) against the wall: the wall point,
  // normal and the face's depth beyond it; false: off the wall (.cpp)
  bool pad_on_wall(Wheel& w, const Eigen::Vector3d& p, const Eigen::Vector3d& u, WallHit* hit,
                   double* depth) const;

  dWorldID world_ = nullptr;
  dJointGroupID group_ = nullptr;
  const WallProbe* probe_ = nullptr;
  double h_ = 0, layer_ = 0, pad_filter_ = 1;
  int made_ = 0;                    // contacts of the last step
  std::vector<Wheel> wheels_;       // by module, in order
  std::vector<int> module_first_;   // index of a module's first wheel; size modules + 1
};

}  // namespace chainsim
