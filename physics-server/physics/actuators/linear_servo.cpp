// The linear servo's force law in ODE. See linear_servo.h.
#include "physics/actuators/linear_servo.h"

#include <algorithm>
#include <cmath>

#include "physics/actuators/wire_value.h"

namespace chainsim {

LinearServo::Params LinearServo::params_of(const ActuatorDef& ad, const JointDef& joint,
                                           const ServoParams& servo, double h_s) {
  Params p;
  p.fmax_n = ad.fmax_n;
  p.l0_m = ad.l0_m;
  p.v_free_m_s = ad.v_free_m_s;
  p.stall_current_a = ad.stall_current_a > 0 ? ad.stall_current_a : servo.supply_v / servo.r;
  p.lo_m = joint.lo;
  p.hi_m = joint.hi;
  p.adc_full_scale_a = servo.adc_full_scale_a;
  p.filter_decay = current_filter_decay(servo.current_filter_tau_s, h_s);
  return p;
}

LinearServo::LinearServo(const Params& params, dWorldID world, dJointID slider, dBodyID child,
                         dBodyID parent, const Eigen::Vector3d& axis_world)
    : params_(params) {
  state_.setpoint_m = std::clamp(0.0, params_.lo_m, params_.hi_m);
  ode_.slider = slider;
  ode_.motor = dJointCreateLMotor(world, nullptr);
  dJointSetLMotorNumAxes(ode_.motor, 1);
  dJointAttach(ode_.motor, child, parent);
  dJointSetLMotorAxis(ode_.motor, 0, 2, axis_world.x(), axis_world.y(), axis_world.z());
  dJointSetLMotorParam(ode_.motor, dParamFMax, 0.0);
}

double LinearServo::setpoint_from_wire(int32_t um) { return um * 1e-6; }

int32_t LinearServo::to_wire(double m) { return round_to_wire(m * 1e6); }

void LinearServo::set_setpoint(double m) {
  if (std::isnan(m)) return;
  state_.setpoint_m = std::clamp(m, params_.lo_m, params_.hi_m);
}

double LinearServo::position() const { return dJointGetSliderPosition(ode_.slider); }

double LinearServo::rate() const { return dJointGetSliderPositionRate(ode_.slider); }

void LinearServo::begin_step(bool driven, double h_s) {
  const Params& p = params_;
  state_.driven = driven;
  state_.law = ForceLaw{};
  if (driven) {
    double d = p.v_free_m_s > 0 ? p.fmax_n / p.v_free_m_s : 0.0;  // back-EMF
    double f0;                                                    // the part known now
    const double u = (state_.setpoint_m - position()) / p.l0_m;
    if (std::fabs(u) < 1.0) {
      f0 = p.fmax_n * u;
      d += p.fmax_n * h_s / p.l0_m;  // the proportional term at the end-of-step position
    } else {
      f0 = u > 0 ? p.fmax_n : -p.fmax_n;
    }
    state_.law = make_force_law(f0, d);
  }
  const double plain = realise_force_law(state_.law, ode_.motor, p.fmax_n);
  if (plain != 0.0) dJointAddSliderForce(ode_.slider, plain);
}

void LinearServo::end_step() {
  state_.force_n = force_after_step(state_.law, rate(), params_.fmax_n);
  state_.current.update(state_.force_n, params_.fmax_n, params_.stall_current_a, state_.driven,
                        params_.filter_decay);
}

double LinearServo::supply_current_a() const {
  return state_.driven ? std::fabs(state_.current.current_a) : 0.0;
}

}  // namespace chainsim
