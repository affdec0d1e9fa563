// DC servomotor model: see servo_model.h for the equations and the scheme.
#include "physics/actuators/servo_model.h"

#include <algorithm>
#include <cmath>

#include "model/units.h"

namespace chainsim {

ServoModel::ServoModel(const ServoParams& params) : p_(params) {
  engaged_ = !(p_.backlash_deg > 0.0);  // backlash: start in the middle of the play
  applied_ = setpoint_;
  if (p_.supply_rail_f > 0.0 && p_.supply_v > 0.0)
    rail_rs_ = p_.supply_sag_ohm > 0.0 ? p_.supply_sag_ohm : std::max(0.0, p_.supply_sag_linear_ohm);
  rail_v_ = p_.supply_v;
}

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
  jh_ = p_.j / h;
  inv_r_ = 1.0 / p_.r;
  drive_gain_ = (1.0 - phi_) / p_.r;
  ci_ = p_.km * (1.0 - phi_) / p_.r;
  er_ = rail_rs_ > 0.0 ? std::exp(-h / (rail_rs_ * p_.supply_rail_f)) : 0.0;
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
  rail_v_ = p_.supply_v;
  time_s_ = 0.0;
  frame_ = -1;
  latch_s_ = -1.0;
  pending_ = applied_;
  delta_ = 0.0;
  wm_ = 0.0;
  engaged_ = !(p_.backlash_deg > 0.0);
  closed_ = false;
  mesh_step_ = false;
}

}  // namespace chainsim
