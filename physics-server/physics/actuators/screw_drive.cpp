// The screw drive's force law in ODE. See screw_drive.h.
#include "physics/actuators/screw_drive.h"

#include <algorithm>
#include <cmath>

#include "physics/actuators/wire_value.h"

namespace chainsim {

ScrewDrive::Params ScrewDrive::params_of(const ActuatorDef& ad, const ServoParams& servo,
                                         double h_s) {
  Params p;
  p.fmax_n = ad.fmax_n;
  p.v_free_m_s = ad.v_free_m_s;
  p.stall_current_a = ad.stall_current_a > 0 ? ad.stall_current_a : servo.supply_v / servo.r;
  p.direction = ad.direction.normalized();
  p.adc_full_scale_a = servo.adc_full_scale_a;
  p.filter_decay = current_filter_decay(servo.current_filter_tau_s, h_s);
  return p;
}

ScrewDrive::ScrewDrive(const Params& params, dWorldID world, dBodyID body) : params_(params) {
  ode_.body = body;
  ode_.motor = dJointCreateLMotor(world, nullptr);
  dJointSetLMotorNumAxes(ode_.motor, 1);
  const Eigen::Vector3d axis = axis_world();
  dJointAttach(ode_.motor, body, nullptr);
  dJointSetLMotorAxis(ode_.motor, 0, 1, axis.x(), axis.y(), axis.z());  // fixed in the body
  dJointSetLMotorParam(ode_.motor, dParamFMax, 0.0);
}

// a servo pulse of +-90 degrees (1.0 .. 2.0 ms) is full reverse .. full forward
double ScrewDrive::setpoint_from_wire(int32_t millideg) { return millideg / 90000.0; }

int32_t ScrewDrive::to_wire(double command) { return round_to_wire(command * 90000.0); }

void ScrewDrive::set_setpoint(double command) {
  if (std::isnan(command)) return;
  state_.command = std::clamp(command, -1.0, 1.0);
}

// (dJointGetLMotorAxis would give the body-frame axis)
Eigen::Vector3d ScrewDrive::axis_world() const {
  const Eigen::Vector3d& d = params_.direction;
  dVector3 ax;
  dBodyVectorToWorld(ode_.body, d.x(), d.y(), d.z(), ax);
  return Eigen::Vector3d(ax[0], ax[1], ax[2]);
}

double ScrewDrive::rate() const {
  const Eigen::Vector3d ax = axis_world();
  const dReal* v = dBodyGetLinearVel(ode_.body);
  return ax[0] * v[0] + ax[1] * v[1] + ax[2] * v[2];
}

void ScrewDrive::begin_step(bool driven, double /*h_s*/) {
  const Params& p = params_;
  state_.driven = driven;
  state_.law = ForceLaw{};
  if (driven) {
    const double d = p.v_free_m_s > 0 ? p.fmax_n / p.v_free_m_s : 0.0;  // back-EMF
    state_.law = make_force_law(p.fmax_n * state_.command, d);
  }
  const double plain = realise_force_law(state_.law, ode_.motor, p.fmax_n);
  if (plain == 0.0) return;
  const Eigen::Vector3d ax = axis_world();
  dBodyAddForce(ode_.body, plain * ax[0], plain * ax[1], plain * ax[2]);
}

void ScrewDrive::end_step() {
  state_.force_n = force_after_step(state_.law, rate(), params_.fmax_n);
  state_.current.update(state_.force_n, params_.fmax_n, params_.stall_current_a, state_.driven,
                        params_.filter_decay);
}

double ScrewDrive::supply_current_a() const {
  return state_.driven ? std::fabs(state_.current.current_a) : 0.0;
}

}  // namespace chainsim
