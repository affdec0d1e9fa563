// The sensors that read another part of the world directly, wired per
// module: each driven actuator's position sensor, the ADC channels that read
// an actuator's filtered motor current, and the touch inputs (any contact on
// a body in the last step). The sensors that keep state of their own
// (accelerometers, wheel encoders) are in sensors.h.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
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
  // a touch sensor: the World's body index, its first digital input bit;
  // with sectors > 1 its switches around the module's axis (module_def.h)
  struct Touch {
    int body = 0;
    int bit = 0;
    int sectors = 1;
    double first_rad = 0, half_width_rad = 0;
    // the module frame from the frame of the ODE body the part is in (parts
    // joined rigidly share one ODE body: module_builder.h)
    Eigen::Isometry3d module_from_body = Eigen::Isometry3d::Identity();
  };
  std::vector<Touch> touch;
};

// which of a sectored touch sensor's switches close (bit k = switch k) when
// its cover is pushed along push_body (in its ODE body's frame: the sum of
// the pushes of what the cover touches, a unit push per geom it touches,
// Contacts::push). The cover is one rigid part on its switches, so
// they feel the resultant: a push mostly along the axis (a wall ahead, or
// the wedge between two outlets met in the middle) closes every switch; one
// that is balanced across it (less than 0.2 of a push: pinched between
// walls) none; otherwise those within half_width of the obstacle's side
// (opposite the push) about the axis close
uint16_t touch_sectors(const ModuleChannels::Touch& t, const Eigen::Vector3d& push_body);

// the touch inputs of a module now (bit n = input n)
uint16_t touch_inputs(const ModuleChannels& channels, const Contacts& contacts);

// a powered module's servo positions (driven[s] = the World's index of servo
// s), motor-current ADC channels and touch inputs into out
void sample_channels(const ModuleChannels& channels, const std::vector<int>& driven,
                     const std::vector<Actuator>& actuators, const Contacts& contacts,
                     ModuleSample* out);

}  // namespace chainsim
