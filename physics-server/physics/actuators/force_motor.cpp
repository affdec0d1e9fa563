// The force actuators' shared motor row and current. See force_motor.h.
#include "physics/actuators/force_motor.h"

#include <algorithm>
#include <cmath>

namespace chainsim {

ForceLaw make_force_law(double known_force_n, double damping_n_s_m) {
  ForceLaw law;
  if (damping_n_s_m > 0) {
    law.damping_n_s_m = damping_n_s_m;
    law.target_rate_m_s = known_force_n / damping_n_s_m;
  } else {
    law.force_n = known_force_n;
  }
  return law;
}

double realise_force_law(const ForceLaw& law, dJointID lmotor, double fmax_n) {
  if (law.damping_n_s_m > 0) {
    dJointSetLMotorParam(lmotor, dParamVel, law.target_rate_m_s);
    dJointSetLMotorParam(lmotor, dParamCFM, 1.0 / law.damping_n_s_m);
    dJointSetLMotorParam(lmotor, dParamFMax, fmax_n);
    return 0.0;
  }
  dJointSetLMotorParam(lmotor, dParamFMax, 0.0);
  return law.force_n;
}

double force_after_step(const ForceLaw& law, double rate_m_s, double fmax_n) {
  return law.damping_n_s_m > 0
             ? std::clamp(law.damping_n_s_m * (law.target_rate_m_s - rate_m_s), -fmax_n, fmax_n)
             : law.force_n;
}

void ForceMotorCurrent::update(double force_n, double fmax_n, double stall_current_a, bool driven,
                               double filter_decay) {
  current_a = driven ? force_n / fmax_n * stall_current_a : 0.0;
  // RC filter of |i|, exact for |i| held over the step (as ServoModel)
  const double a = std::fabs(current_a);
  filtered_current_a = a + (filtered_current_a - a) * filter_decay;
}

uint16_t ForceMotorCurrent::adc_counts(double adc_full_scale_a) const {
  if (!(adc_full_scale_a > 0.0)) return 0;
  const double c = std::floor(filtered_current_a / adc_full_scale_a * 1023.0 + 0.5);
  return static_cast<uint16_t>(std::clamp(c, 0.0, 1023.0));
}

double current_filter_decay(double tau_s, double h_s) {
  return tau_s > 0 ? std::exp(-h_s / tau_s) : 0.0;
}

}  // namespace chainsim
