// Position, motor-current and touch channels. See module_channels.h.
#include "physics/sensors/module_channels.h"

namespace chainsim {

uint16_t touch_inputs(const ModuleChannels& channels, const Contacts& contacts) {
  uint16_t bits = 0;
  for (const auto& [body, bit] : channels.touch)
    if (contacts.touched(body)) bits |= static_cast<uint16_t>(1u << bit);
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
