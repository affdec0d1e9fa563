// Position, motor-current and touch channels. See module_channels.h.
#include "physics/sensors/module_channels.h"

#include <cmath>

namespace chainsim {

uint16_t touch_sectors(const ModuleChannels::Touch& t, const Eigen::Vector3d& push_body) {
  const uint16_t all = static_cast<uint16_t>((1u << t.sectors) - 1u);
  const Eigen::Vector3d n = t.module_from_body.linear() * push_body;
  if (std::fabs(n.x()) > 0.8 * n.norm()) return all;   // pushes along the axis: every switch
  if (std::hypot(n.y(), n.z()) < 0.2) return 0;          // pinched, balanced across: the cover does not tilt
  const double dir = std::atan2(-n.y(), -n.z());   // the obstacle's side: 0 = up (+z), pi/2 = left (+y)
  uint16_t bits = 0;
  for (int k = 0; k < t.sectors; ++k) {
    const double a = t.first_rad + 2 * M_PI * k / t.sectors;
    const double off = std::remainder(dir - a, 2 * M_PI);
    if (std::fabs(off) <= t.half_width_rad) bits |= static_cast<uint16_t>(1u << k);
  }
  return bits;
}

uint16_t touch_inputs(const ModuleChannels& channels, const Contacts& contacts) {
  uint16_t bits = 0;
  for (const ModuleChannels::Touch& t : channels.touch) {
    if (!contacts.touched(t.body)) continue;
    if (t.sectors <= 1) {
      bits |= static_cast<uint16_t>(1u << t.bit);
      continue;
    }
    bits |= static_cast<uint16_t>(touch_sectors(t, contacts.push(t.body)) << t.bit);
  }
  return bits;
}

void sample_channels(const ModuleChannels& channels, const std::vector<int>& driven,
                     const std::vector<Actuator>& actuators, const Contacts& contacts,
                     ModuleSample* out) {
  for (size_t s = 0; s < driven.size(); ++s)
    out->servo_position_wire[s] = actuators[driven[s]].visit([](const auto& a) { return a.position_wire(); });
  for (int c = 0; c < channels.n_adc; ++c) {
    const int a = channels.adc_actuator[c];
    if (a >= 0) out->adc[c] = actuators[a].visit([](const auto& x) { return x.adc_counts(); });
  }
  out->digital_in |= touch_inputs(channels, contacts);
}

}  // namespace chainsim
