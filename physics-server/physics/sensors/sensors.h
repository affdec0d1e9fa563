// Module sensors the World keeps state for (paper 4.3), and the traveller's
// wheel friction (paper 3.3.6). Servo position, motor current and touch are
// read from the actuators and contacts (module_channels.h); this file does:
//
//  * Accelerometer (paper 4.3.2, Fig. 8): 3 axes on ADC channels c, c+1, c+2
//    = the sensor frame's x, y, z (SensorDef::orientation; by default the
//    module's axes: x forward, y left, z up). It measures the specific force
//    at its part's centre of mass: f = a - g (a = that point's acceleration over
//    the last step, (v_after - v_before) / h; g = (0, 0, -gravity)), so a
//    sensor at rest reads +1 g on the axis pointing up. Then a first-order
//    low-pass filter (bandwidth_hz, 0 = none; the filter starts settled at
//    rest), then
//        counts = round(512 + (f / g0 + n) * 512 / range_g), clamped to 0..1023
//    g0 = 9.80665 m/s^2; range_g = 3 gives 170.7 counts per g (0 g = 512,
//    +1 g = 683, -1 g = 341, +-3 g = the ends). n: Gaussian noise in g,
//    standard deviation noise_g, a pure function of (world seed, module,
//    sensor, axis, sample time): deterministic, the same however often a
//    time is sampled.
//  * Wheel encoder (paper 4.3.3): a counter of the hinge's rotation (child
//    relative to parent about the axis), round(turned angle / 2 pi *
//    counts_per_rev), signed, 0 as assembled (the wheel starts half-way
//    between two counts, so solver jitter does not toggle the count). The
//    angle is unwrapped every step (exact while a wheel turns less than half
//    a turn per step). It counts even while the module is unpowered (which
//    reads zero).
//  * Joint friction (JointDef::friction_nm_s_rad, the traveller's wheels): a
//    torque -c w on a hinge, realised as a one-axis ODE angular motor with
//    target rate 0 and CFM = 1/c (an exactly implicit damper, stable for any c
//    and inertia; the servo model uses the same device).
//
// No allocation after construction: step_end() and sample() only read and
// write preallocated state.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "model/module_def.h"
#include "physics/module_builder.h"
#include "physics/sensors/module_sample.h"

namespace chainsim {


class Sensors {
 public:
  void init(dWorldID world, uint64_t seed, double gravity_m_s2);
  // module `module`'s accelerometers, wheel encoders and joint friction;
  // parts: the ODE objects of def's bodies and joints as built in the module
  // frame `frame_rotation` (module -> world)
  void add_module(int module, const ModuleDef& def, const ModuleBodies& parts,
                  const Eigen::Matrix3d& frame_rotation);
  // after each physics step of length h_s
  void step_end(double h_s);
  // fill module `module`'s accelerometer ADC channels and counters (n_adc and
  // n_counters grow to cover them; values stay 0 if unpowered)
  void sample(int module, bool powered, int64_t time_us, ModuleSample* out) const;

 private:
  struct Accel {
    int module = -1;
    int sensor = 0;  // index in ModuleDef::sensors (noise stream)
    dBodyID body = nullptr;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the part's centre of mass in body's frame
    Eigen::Matrix3d body_to_sensor;  // R_bs^T: body-frame vector -> sensor frame
    int channel = 0;
    double range_g = 3.0, noise_g = 0.0;
    double alpha = 1.0;                                // low-pass: f += alpha (f_new - f)
    Eigen::Vector3d v_prev = Eigen::Vector3d::Zero();  // world, m/s
    Eigen::Vector3d f = Eigen::Vector3d::Zero();  // filtered specific force, sensor frame, m/s^2
  };
  struct Encoder {
    int module = -1;
    dJointID hinge = nullptr;
    int channel = 0;
    int counts_per_rev = 360;
    double last_angle = 0;  // as ODE reports it, (-pi, pi]
    double turned = 0;      // unwrapped, rad
  };

  dWorldID world_ = nullptr;
  uint64_t seed_ = 0;
  Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();
  double h_ = -1;  // step the filter constants are for
  std::vector<Accel> accels_;
  std::vector<Encoder> encoders_;
  std::vector<double> bandwidth_;  // per accelerometer, Hz
};

}  // namespace chainsim
