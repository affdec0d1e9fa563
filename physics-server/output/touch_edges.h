// Touch edges, for the bus log and the events file: each time a module's
// touch input changes. The bus log keeps its line "touch endpoint=<m>
// level=<0|1>" per module, level 1 while any of its touch sensors' inputs
// is set (input 0 for a module without one; every module starts at 0), so a
// run's bus.log shows when the chain's touch module met something;
// the events file gets one event per touch sensor of the module types
// (SensorColumn::Source::DigitalIn), named after the sensor.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "output/trace_writer.h"
#include "physics/world.h"

namespace chainsim {

class TouchEdges {
 public:
  // columns: the chain's sensor columns (sensor_columns); its digital inputs are watched
  TouchEdges(int modules, const std::vector<SensorColumn>& columns);

  // line(const char*) for each module whose touch level changed since the last
  // call, then event(module, sensor, level) for each touch sensor that did,
  // in module order
  template <class Line, class Event>
  void sample(const World& world, Line line, Event event) {
    for (int m = 0; m < static_cast<int>(level_.size()); ++m) {
      const uint16_t in = world.digital_inputs(m);
      const uint8_t level = (in & mask_[static_cast<size_t>(m)]) != 0;
      if (level != level_[m]) {
        level_[m] = level;
        line(touch_line(m, level).c_str());
      }
      for (Watched& w : inputs_) {
        if (w.module != m) continue;
        const uint8_t v = (in >> w.bit) & 1u;
        if (v == w.level) continue;
        w.level = v;
        event(m, w.sensor, v);
      }
    }
  }

  static std::string touch_line(int module, unsigned level);

 private:
  struct Watched {
    int module = 0;
    int bit = 0;
    std::string sensor;
    uint8_t level = 0;
  };
  std::vector<uint8_t> level_;  // last logged level, per module
  std::vector<uint16_t> mask_;  // per module: the inputs of its touch sensors (input 0 without any)
  std::vector<Watched> inputs_;
};

}  // namespace chainsim
