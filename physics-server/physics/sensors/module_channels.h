// The sensors that read another part of the world directly, wired per
// module: each driven actuator's position sensor, the ADC channels that read
// an actuator's filtered motor current, and the touch inputs (any contact on
// a body in the last step). The sensors that keep state of their own
// (accelerometers, wheel encoders) are in sensors.h.
#pragma once

#include <utility>
#include <vector>

#include "physics/actuators/actuator.h"
#include "physics/contact.h"
#include "physics/sensors/module_sample.h"

namespace chainsim {

struct ModuleChannels {
  int n_adc = 0;
  // ADC channel -> the World's index of the actuator whose current it reads;
  // -1: not a current channel
  int adc_actuator[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  std::vector<std::pair<int, int>> touch;  // (the World's body index, digital input bit)
};

// the touch inputs of a module now (bit n = input n)
uint16_t touch_inputs(const ModuleChannels& channels, const Contacts& contacts);

// a powered module's servo positions (driven[s] = the World's index of servo
// s), motor-current ADC channels and touch inputs into out
void sample_channels(const ModuleChannels& channels, const std::vector<int>& driven,
                     const std::vector<Actuator>& actuators, const Contacts& contacts,
                     ModuleSample* out);

}  // namespace chainsim
