// The ODE world of one run: environment, the chain of modules, their actuator
// models and sensors. Knows nothing of processes or sockets: the lockstep
// server feeds it set-points and samples its sensors between steps.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "environment/environment.h"
#include "environment/material.h"
#include "model/module_def.h"
#include "physics/actuators/servo_model.h"

namespace chainsim {

struct WorldConfig {
  int64_t dt_us = 500;                 // physics step
  uint64_t seed = 1;                   // seeds ODE's dRandSetSeed
  std::vector<std::string> chain;      // module type names, head first
  Eigen::Vector3d head_position{0, 0, 0.02};  // centre of the head's front face, m
  double heading_rad = 0.0;            // the chain points along +x rotated by this about z
  // if set, overrides heading_rad: the head's front-face frame (module frame)
  // -> world; the chain is laid along its -x (e.g. along a pipe's axis)
  std::optional<Eigen::Quaterniond> head_orientation;
  Material ground;                     // module-environment contact (pairs not in environment.contacts)
  EnvironmentConfig environment;       // plane, terrain, pipe or mesh (environment.h)
  ServoParams servo;                   // every servo's model (paper Table 1 defaults)
  double gravity_m_s2 = 9.81;
  // --- added by the physics implementation ---
  Material module_contact{0.3, 0.0, 0.2, 1e-5};  // module-module contact (plastic on plastic)
  int solver_iterations = 30;          // ODE QuickStep iterations (see world.cpp for the measurements)
  // more module types (e.g. test fixtures, types loaded from files): `chain`
  // names are looked up here first, then among the built-ins
  std::vector<ModuleDef> module_types;
  // diagnostics: read every contact's force back (World::body_contact_force)
  bool log_contact_forces = false;
};

// what one module's sensors read at a sample time; what TickBegin carries
struct ModuleSample {
  int n_servos = 0;
  // the actuator's position sensor, in its set-point unit (World::ServoKind):
  // rotary servo: output shaft angle, rad (potentiometer); linear servo: slider
  // position, m; screw drive (no position sensor): its drive command, -1..1
  double servo_angle_rad[4] = {};
  int n_adc = 0;
  uint16_t adc[8] = {};             // 10-bit counts
  uint16_t digital_in = 0;          // bit n = digital input n
  int n_counters = 0;
  int32_t counter[4] = {};
};

class World {
 public:
  explicit World(const WorldConfig& config);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int module_count() const;
  const std::string& module_type(int module) const;
  int servo_count(int module) const;

  // Servo s of module m = the s-th actuator of its ModuleDef that firmware
  // drives (driven_servo_actuators: servos, linear servos and screw drives in
  // definition order; rotation: 0 = pitch, 1 = yaw). The set-point's unit
  // depends on the kind:
  //  * Rotary (ActuatorType::Servo): radians, see below. Wire: millidegrees.
  //  * Linear (LinearServo): the slider position, metres (0 = as assembled,
  //    + = the child moved along the axis), clamped to the slider's limits.
  //    Wire: micrometres (set-point and measured position alike).
  //  * Screw (ScrewDrive): the signed drive command u, -1..1 (a fraction of
  //    the supply voltage, like a PWM duty cycle; the force law is in
  //    module_library.h), clamped. Wire: per mille (-1000..1000); its
  //    "measured position" echoes the command.
  // Rotary angles are the joint's:
  // 0 as assembled (straight), + = the child side turned positively about the
  // joint axis (rotation module: pitch + lifts the module's rear, yaw + swings
  // it to the right); range +-90 degrees. The servo's own 0..180 degree scale
  // is this angle + 90 degrees.
  // set-point of servo s of module m (radians, metres or -1..1, above);
  // clamped to the servo's range
  void set_servo_setpoint(int module, int servo, double rad);
  enum class ServoKind { Rotary, Linear, Screw };
  ServoKind servo_kind(int module, int servo) const;
  // wire units (cs_tick_begin/end servo_pos/servo_setpoint) <-> set-point units
  static double servo_from_wire(ServoKind kind, int32_t wire);
  static int32_t servo_to_wire(ServoKind kind, double value);
  // a disabled servo gets no drive voltage (no pulses): it is limp
  void set_servo_enabled(int module, int servo, bool enabled);
  // an unpowered module: all servos limp, sensors read zero (limp mode after a fault)
  void set_module_powered(int module, bool powered);

  // advance the world by one physics step (dt_us); never allocates
  void step();
  int64_t time_us() const;
  int64_t dt_us() const;

  // sensor readings of module m now
  void sample(int module, ModuleSample* out) const;

  // supply current drawn by module m now, A (sum over its motors)
  double module_supply_current_a(int module) const;

  // mass-weighted centre of all module bodies, world frame, m
  Eigen::Vector3d chain_com() const;

  // --- diagnostics and test fixtures (added by the physics implementation) ---
  struct BodyState {
    double mass_kg = 0;
    Eigen::Matrix3d inertia_kg_m2;        // about the centre of mass, body frame (from ODE)
    Eigen::Vector3d position;             // centre of mass, world frame, m
    Eigen::Vector4d quaternion_wxyz;      // body frame -> world
    Eigen::Vector3d linear_velocity;      // m/s
  };
  int body_count(int module) const;
  const std::string& body_name(int module, int body) const;
  BodyState body_state(int module, int body) const;
  // true hinge angle (slider position, m; screw: the body's speed along its
  // drive axis, m/s), even if unpowered
  double servo_angle_rad(int module, int servo) const;
  double servo_setpoint_rad(int module, int servo) const;   // in set-point units
  double servo_current_a(int module, int servo) const;      // motor current now (signed)
  double servo_filtered_current_a(int module, int servo) const;
  // effort of the last step: rotary N m (Kt dz(i)); linear servo, screw drive N
  double servo_effort(int module, int servo) const;
  // fix a body to the static environment where it is now (e.g. a hanging chain)
  void pin_body(int module, int body);
  // a torque (world frame, N m) on a body during the next step only (a test
  // load; call before every step for a constant one)
  void add_body_torque(int module, int body, const Eigen::Vector3d& torque_nm);
  // a force (world frame, N) at a body's centre of mass during the next step
  // only (a test load: pushing a traveller along the floor)
  void add_body_force(int module, int body, const Eigen::Vector3d& force_n);
  // largest distance between the two docking-face frames of a docked pair
  // (back face of k, front face of k+1), each computed from its own body: how
  // much the docking joints stretch, m
  double max_docking_error_m() const;
  // contact joints created in the last step
  int last_contact_count() const;
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
  // the ordinary contacts' forces on a body in the last step (needs
  // WorldConfig::log_contact_forces; wheel contacts are in wheel_state)
  struct ContactForce {
    double normal_n = 0;                              // sum of the normal force magnitudes, N
    Eigen::Vector3d force = Eigen::Vector3d::Zero();  // total, world frame, N
    int contacts = 0;
  };
  ContactForce body_contact_force(int module, int body) const;

  // trace: one CSV header line, then one row per call; fixed formatting so
  // that equal states give equal bytes
  std::string trace_header() const;
  void append_trace_row(std::string* out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace chainsim
