// The ODE world of one run: environment, the chain of modules, their actuator
// models and sensors. Knows nothing of processes or sockets: the lockstep
// server feeds it set-points and samples its sensors between steps.
//
// Files: world.cpp (assembly and the step), module_builder.cpp (a module's
// bodies and joints), contact.cpp (the near callback, friction, materials),
// actuators/ (one file per kind), wheels/ (wheels and pads on the wall),
// sensors/ (sampling), placement.cpp.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/module_def.h"
#include "physics/actuators/actuator.h"
#include "physics/chain_model.h"
#include "physics/sensors/module_sample.h"
#include "physics/world_config.h"

namespace chainsim {

// a scene the World cannot be built from as asked: a body that starts inside
// the environment, a joint between parts already rigidly joined. The message
// names the module and body; the run refuses the scene (exit 1).
struct WorldSetupError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class World {
 public:
  // chain: compiled from config (compile_chain: the definitions and the
  // frames its head pose lays); throws WorldSetupError naming a body that
  // starts more than 1 mm inside the environment
  World(const WorldConfig& config, const ChainModel& chain);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int module_count() const;
  const std::string& module_type(int module) const;
  int servo_count(int module) const;

  // Servo s of module m = the s-th actuator of its ModuleDef that firmware
  // drives (driven_servo_actuators: servos, linear servos, screw drives and
  // DC motors in definition order; rotation: 0 = pitch, 1 = yaw). Values are
  // in the actuator's unit: radians (rotary), metres (linear), the -1..1
  // drive command (screw drive, DC motor); each kind's file (actuators/) says
  // what they mean.
  ServoKind servo_kind(int module, int servo) const;
  // the set-point in the actuator's unit, clamped to its range (NaN: ignored)
  void set_servo_setpoint(int module, int servo, double setpoint);
  // the set-point from the wire (cs_tick_end.servo_setpoint), in the actuator's wire unit
  void set_servo_setpoint_wire(int module, int servo, int32_t setpoint_wire);
  // a disabled servo gets no drive voltage (no pulses): it is limp
  void set_servo_enabled(int module, int servo, bool enabled);
  // an unpowered module: all servos limp, sensors read zero (limp mode after a fault)
  void set_module_powered(int module, bool powered);

  // advance the world by one physics step (dt_us); never allocates
  void step();
  int64_t time_us() const;
  // the exact solver (WorldConfig::Solver::Exact): the steps whose LCP met
  // a degenerate pivot (ODE's "LCP internal error"; the step went on with
  // the solution found so far); 0 for QuickStep
  int64_t degenerate_lcp_steps() const;
  int64_t dt_us() const;

  // sensor readings of module m now, in wire units
  void sample(int module, ModuleSample* out) const;
  // module m's digital inputs now (its touch sensors; 0 when unpowered)
  uint16_t digital_inputs(int module) const;

  // supply current drawn by module m now, A (sum over its motors)
  double module_supply_current_a(int module) const;

  // mass-weighted centre of all module bodies, world frame, m
  Eigen::Vector3d chain_com() const;

  // --- what traces, diagnostics and tests read ---
  struct BodyState {
    double mass_kg = 0;
    Eigen::Matrix3d inertia_kg_m2;        // about the centre of mass, body frame (from ODE)
    Eigen::Vector3d position;             // centre of mass, world frame, m
    Eigen::Vector4d quaternion_wxyz;      // body frame -> world
    Eigen::Vector3d linear_velocity;      // m/s
    Eigen::Vector3d angular_velocity;     // rad/s, world frame
  };
  int body_count(int module) const;
  const std::string& body_name(int module, int body) const;
  BodyState body_state(int module, int body) const;
  double servo_setpoint(int module, int servo) const;   // in the actuator's unit
  // what its position sensor reads, in the actuator's unit, even when
  // unpowered: hinge angle, slider position; a screw drive or DC motor echoes
  // its command
  double servo_position(int module, int servo) const;
  // rad/s (hinge; DC motor: its hinge) or m/s (slider; screw drive: its
  // body's speed along the drive axis)
  double servo_rate(int module, int servo) const;
  double servo_current_a(int module, int servo) const;      // motor current now (signed)
  double servo_filtered_current_a(int module, int servo) const;
  // effort of the last step: rotary N m (Kt dz(i)); linear servo, screw drive
  // N; DC motor N m
  double servo_effort(int module, int servo) const;
  // fix a body to the static environment where it is now (e.g. a hanging chain)
  void pin_body(int module, int body);
  // a torque (world frame, N m) on a body during the next step only (a test
  // load; call before every step for a constant one)
  void add_body_torque(int module, int body, const Eigen::Vector3d& torque_nm);
  // a force (world frame, N) at a body's centre of mass during the next step
  // only (a test load: pushing a traveller along the floor)
  void add_body_force(int module, int body, const Eigen::Vector3d& force_n);
  // the docks' forces in the last step, when they are joints
  // (WorldConfig::dock); dock k joins module k's back face to module k + 1's
  // front face. What module k passes to module k + 1 across the faces:
  // axial along k + 1's front face's x (+: k pulls k + 1 towards itself,
  // tension), shear across it; the moment about the faces' centre across
  // the axis (bend) and about it (twist); and the angle between the two
  // faces' axes
  struct DockForce {
    double axial_n = 0, shear_n = 0, bend_nm = 0, twist_nm = 0, bend_deg = 0;
  };
  int dock_count() const;  // 0 when docked parts share one body
  DockForce dock_force(int dock) const;
  // largest distance between the two docking-face frames of a docked pair
  // (back face of k, front face of k+1), each computed from its own part: 0
  // up to rounding where docked parts share one ODE body (the default;
  // with WorldConfig::dock the ball joint's error), m
  double max_docking_error_m() const;
  // contact joints created in the last step
  int last_contact_count() const;
  // the deepest contact of the last step, between a module body and the
  // environment or another module (module -1: no contact)
  struct Penetration {
    double depth_m = 0;
    int module = -1;
    int body = -1;
  };
  Penetration deepest_contact() const;
  // the wheels of module m's wheel sets (model/wheel_def.h), in file order:
  // name (set name + index), and in the last step whether it touched the
  // wall, its reach, normal force and friction across it (N)
  struct WheelState {
    bool on = false;
    double reach_m = 0, normal_n = 0, across_n = 0;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // wall point, world
  };
  int wheel_count(int module) const;
  const std::string& wheel_name(int module, int wheel) const;
  WheelState wheel_state(int module, int wheel) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace chainsim
