// Accelerometers, wheel encoders and joint friction. See sensors.h.
#include "physics/sensors/sensors.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "physics/sensors/module_sample.h"
#include "model/units.h"
#include "physics/splitmix64.h"

namespace chainsim {
namespace {

constexpr double kG0 = 9.80665;         // standard gravity, m/s^2: the sensor's "g"
constexpr double kFrictionFMax = 10.0;  // N m; far above any wheel's friction torque

Eigen::Matrix3d body_rotation(dBodyID b) {
  const dReal* q = dBodyGetQuaternion(b);
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
}

// velocity of a point fixed in body b (body frame), world frame
Eigen::Vector3d point_velocity(dBodyID b, const Eigen::Vector3d& point) {
  dVector3 v;
  dBodyGetRelPointVel(b, point.x(), point.y(), point.z(), v);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

// standard normal deviate for one (seed, module, sensor, axis, time) (Box-Muller)
double gaussian(uint64_t seed, int module, int sensor, int axis, int64_t time_us) {
  uint64_t k = splitmix64(seed);
  k = splitmix64(k ^ static_cast<uint64_t>(module));
  k = splitmix64(k ^ (static_cast<uint64_t>(sensor) << 8 | static_cast<uint64_t>(axis)));
  k = splitmix64(k ^ static_cast<uint64_t>(time_us));
  const uint64_t k2 = splitmix64(k);
  const double u1 = (static_cast<double>(k >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = static_cast<double>(k2 >> 11) * 0x1.0p-53;         // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

// turn a step's raw angle change into (-pi, pi]
double wrap(double a) {
  while (a > kPi) a -= 2.0 * kPi;
  while (a <= -kPi) a += 2.0 * kPi;
  return a;
}

}  // namespace

void Sensors::init(dWorldID world, uint64_t seed, double gravity_m_s2) {
  world_ = world;
  seed_ = seed;
  gravity_ = Eigen::Vector3d(0, 0, -gravity_m_s2);
}

void Sensors::add_module(int module, const ModuleDef& def, const ModuleBodies& parts,
                         const Eigen::Matrix3d& frame_rotation) {
  const std::vector<dBodyID>& bodies = parts.bodies;
  const std::vector<dJointID>& joints = parts.joints;
  for (size_t j = 0; j < def.joints.size(); ++j) {
    const JointDef& jd = def.joints[j];
    if (jd.type != JointType::Hinge || !(jd.friction_nm_s_rad > 0)) continue;
    dJointID m = dJointCreateAMotor(world_, nullptr);
    dJointAttach(m, bodies[jd.child], bodies[jd.parent]);
    dJointSetAMotorMode(m, dAMotorUser);
    dJointSetAMotorNumAxes(m, 1);
    const Eigen::Vector3d axis = frame_rotation * jd.axis.normalized();
    dJointSetAMotorAxis(m, 0, 1, axis.x(), axis.y(), axis.z());  // fixed in the child
    dJointSetAMotorParam(m, dParamVel, 0.0);
    dJointSetAMotorParam(m, dParamFMax, kFrictionFMax);
    dJointSetAMotorParam(m, dParamCFM, 1.0 / jd.friction_nm_s_rad);
  }

  for (size_t k = 0; k < def.sensors.size(); ++k) {
    const SensorDef& sd = def.sensors[k];
    if (sd.type == SensorType::Accelerometer) {
      Accel a;
      a.module = module;
      a.sensor = static_cast<int>(k);
      a.body = bodies[sd.body];
      a.point = parts.offsets[sd.body].translation();
      // sensor axes in the ODE body's frame: R_bs = R_offset R_mp^T R_ms (p: the part)
      const Eigen::Matrix3d r_bs =
          parts.offsets[sd.body].linear() *
          def.bodies[sd.body].pose.orientation.normalized().toRotationMatrix().transpose() *
          sd.orientation.normalized().toRotationMatrix();
      a.body_to_sensor = r_bs.transpose();
      a.channel = sd.channel;
      a.range_g = sd.range_g;
      a.noise_g = sd.noise_g;
      a.v_prev = point_velocity(a.body, a.point);
      // settled at rest: -g only
      a.f = a.body_to_sensor * body_rotation(a.body).transpose() * (-gravity_);
      accels_.push_back(a);
      bandwidth_.push_back(sd.bandwidth_hz);
    } else if (sd.type == SensorType::WheelEncoder) {
      Encoder e;
      e.module = module;
      e.hinge = joints[sd.joint];
      e.channel = sd.channel;
      e.counts_per_rev = sd.counts_per_rev;
      e.last_angle = dJointGetHingeAngle(e.hinge);
      encoders_.push_back(e);
    }
  }
  h_ = -1;  // filter constants recomputed at the next step
}

void Sensors::step_end(double h_s) {
  if (h_s != h_) {
    h_ = h_s;
    for (size_t k = 0; k < accels_.size(); ++k)
      accels_[k].alpha = bandwidth_[k] > 0 ? 1.0 - std::exp(-2.0 * kPi * bandwidth_[k] * h_s) : 1.0;
  }
  for (Accel& a : accels_) {
    const Eigen::Vector3d v = point_velocity(a.body, a.point);
    const Eigen::Vector3d acc = (v - a.v_prev) / h_s;
    a.v_prev = v;
    const Eigen::Vector3d f =
        a.body_to_sensor * (body_rotation(a.body).transpose() * (acc - gravity_));
    a.f += a.alpha * (f - a.f);
  }
  for (Encoder& e : encoders_) {
    const double angle = dJointGetHingeAngle(e.hinge);
    e.turned += wrap(angle - e.last_angle);
    e.last_angle = angle;
  }
}

void Sensors::sample(int module, bool powered, int64_t time_us, ModuleSample* out) const {
  for (const Accel& a : accels_) {
    if (a.module != module) continue;
    out->n_adc = std::max(out->n_adc, a.channel + 3);
    if (!powered) continue;
    for (int axis = 0; axis < 3; ++axis) {
      double g = a.f[axis] / kG0;
      if (a.noise_g > 0) g += a.noise_g * gaussian(seed_, module, a.sensor, axis, time_us);
      const double counts = std::floor(512.0 + g * 512.0 / a.range_g + 0.5);
      out->adc[a.channel + axis] = static_cast<uint16_t>(std::clamp(counts, 0.0, 1023.0));
    }
  }
  for (const Encoder& e : encoders_) {
    if (e.module != module) continue;
    out->n_counters = std::max(out->n_counters, e.channel + 1);
    if (!powered) continue;
    const double counts = std::floor(e.turned / (2.0 * kPi) * e.counts_per_rev + 0.5);
    out->counter[e.channel] = static_cast<int32_t>(std::clamp(counts, -2147483648.0, 2147483647.0));
  }
}

}  // namespace chainsim
