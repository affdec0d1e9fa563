// The DC motor's torque law in ODE. See dc_motor.h.
#include "physics/actuators/dc_motor.h"

#include <algorithm>
#include <cmath>

#include "physics/actuators/screw_drive.h"

namespace chainsim {

DcMotor::Params DcMotor::params_of(const ActuatorDef& ad, const ServoParams& servo, double h_s) {
  Params p;
  p.stall_torque_nm = ad.fmax_n;
  p.free_speed_rad_s = ad.v_free_m_s;
  p.stall_current_a = ad.stall_current_a > 0 ? ad.stall_current_a : servo.supply_v / servo.r;
  p.adc_full_scale_a = servo.adc_full_scale_a;
  p.filter_decay = current_filter_decay(servo.current_filter_tau_s, h_s);
  return p;
}

DcMotor::DcMotor(const Params& params, dWorldID world, dJointID hinge, dBodyID child,
                 dBodyID parent, const Eigen::Vector3d& axis_world)
    : params_(params) {
  ode_.hinge = hinge;
  ode_.motor = dJointCreateAMotor(world, nullptr);
  dJointAttach(ode_.motor, child, parent);
  dJointSetAMotorMode(ode_.motor, dAMotorUser);
  dJointSetAMotorNumAxes(ode_.motor, 1);
  dJointSetAMotorAxis(ode_.motor, 0, 1, axis_world.x(), axis_world.y(), axis_world.z());
  dJointSetAMotorParam(ode_.motor, dParamFMax, 0.0);
}

double DcMotor::setpoint_from_wire(int32_t millideg) { return ScrewDrive::setpoint_from_wire(millideg); }
int32_t DcMotor::to_wire(double command) { return ScrewDrive::to_wire(command); }

void DcMotor::set_setpoint(double command) {
  if (std::isnan(command)) return;
  state_.command = std::clamp(command, -1.0, 1.0);
}

double DcMotor::rate() const { return dJointGetHingeAngleRate(ode_.hinge); }

void DcMotor::begin_step(bool driven, double /*h_s*/) {
  const Params& p = params_;
  state_.driven = driven;
  state_.law = ForceLaw{};
  if (!driven) {  // no drive: the gear turns freely
    dJointSetAMotorParam(ode_.motor, dParamFMax, 0.0);
    return;
  }
  // back-EMF as the row's damping (free speed > 0: validated)
  state_.law = make_force_law(p.stall_torque_nm * state_.command, p.stall_torque_nm / p.free_speed_rad_s);
  dJointSetAMotorParam(ode_.motor, dParamVel, state_.law.target_rate_m_s);
  dJointSetAMotorParam(ode_.motor, dParamCFM, 1.0 / state_.law.damping_n_s_m);
  dJointSetAMotorParam(ode_.motor, dParamFMax, p.stall_torque_nm);
}

void DcMotor::end_step() {
  state_.torque_nm = force_after_step(state_.law, rate(), params_.stall_torque_nm);
  state_.current.update(state_.torque_nm, params_.stall_torque_nm, params_.stall_current_a,
                        state_.driven, params_.filter_decay);
}

double DcMotor::supply_current_a() const {
  return state_.driven ? std::fabs(state_.current.current_a) : 0.0;
}

}  // namespace chainsim
