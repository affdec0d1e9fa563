// DC servomotor model: see servo_model.h for the equations and the scheme.
#include "servo_model.h"

#include <algorithm>
#include <cmath>

namespace chainsim {

ServoModel::ServoModel(const ServoParams& params) : p_(params) {}

void ServoModel::update_constants(double h) {
  h_ = h;
  const double tau_e = p_.l / p_.r;
  if (tau_e > 0.0) {
    const double x = h / tau_e;
    e_ = std::exp(-x);
    // (1 - e^-x)/x, with its series near 0 to avoid cancellation
    phi_ = x < 1e-6 ? 1.0 - x / 2.0 : -std::expm1(-x) / x;
  } else {  // no inductance: the current follows the voltage at once
    e_ = 0.0;
    phi_ = 0.0;
  }
  ef_ = p_.current_filter_tau_s > 0.0 ? std::exp(-h / p_.current_filter_tau_s) : 0.0;
}

ServoModel::StepLaw ServoModel::begin_step(double theta, double w, double h) {
  if (h != h_) update_constants(h);
  drive_ = enabled_;
  StepLaw law;
  // rotor inertia, implicit on the joint rate: -J (w' - w)/h
  const double jh = p_.j / h;
  // step-average current = i0 - ci w' (affine in the end-of-step rate w')
  double i0, ci;
  if (drive_) {
    ea_ = std::clamp(p_.kp * (setpoint_ - theta), -p_.supply_v, p_.supply_v);
    i0 = (1.0 - phi_) * ea_ / p_.r + phi_ * i_;
    ci = p_.km * (1.0 - phi_) / p_.r;
  } else {
    ea_ = 0.0;
    i0 = phi_ * i_;   // free-wheeling current, no back-EMF path
    ci = 0.0;
  }
  if (p_.i_threshold_a > 0.0) {
    // static friction: torque Kt dz(i_avg); the branch of dz from the
    // prediction w' = w, then affine (implicit) within it
    const double i_pred = i0 - ci * w;
    if (i_pred > p_.i_threshold_a) {
      i0 -= p_.i_threshold_a;
    } else if (i_pred < -p_.i_threshold_a) {
      i0 += p_.i_threshold_a;
    } else {
      i0 = 0.0;
      ci = 0.0;
    }
  }
  // step-average electromagnetic torque = t0 - c_emf w'
  const double t0 = p_.kt * i0, c_emf = p_.kt * ci;
  law.damping = c_emf + p_.b + jh;
  law.target_rate = (t0 + jh * w) / law.damping;
  return law;
}

void ServoModel::end_step(double w_next) {
  const double i_inf = drive_ ? (ea_ - p_.km * w_next) / p_.r : 0.0;
  i_mean_ = (1.0 - phi_) * i_inf + phi_ * i_;
  i_ = i_inf + (i_ - i_inf) * e_;
  // RC filter of |i|, exact for the step-average |i| held over the step
  i_f_ = std::fabs(i_mean_) + (i_f_ - std::fabs(i_mean_)) * ef_;
}

double ServoModel::dead_zone(double i) const {
  const double th = p_.i_threshold_a;
  if (!(th > 0.0)) return i;
  if (i > th) return i - th;
  if (i < -th) return i + th;
  return 0.0;
}

uint16_t ServoModel::adc_counts() const {
  if (!(p_.adc_full_scale_a > 0.0)) return 0;
  const double c = std::floor(i_f_ / p_.adc_full_scale_a * 1023.0 + 0.5);
  return static_cast<uint16_t>(std::clamp(c, 0.0, 1023.0));
}

void ServoModel::reset_state() {
  i_ = 0.0;
  i_f_ = 0.0;
  i_mean_ = 0.0;
  ea_ = 0.0;
}

}  // namespace chainsim
