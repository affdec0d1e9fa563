// Touch edges of the bus log and the events file. See touch_edges.h.
#include "output/touch_edges.h"

namespace chainsim {

TouchEdges::TouchEdges(int modules, const std::vector<SensorColumn>& columns)
    : level_(static_cast<size_t>(modules), 0), mask_(static_cast<size_t>(modules), 0) {
  for (const SensorColumn& c : columns)
    if (c.source == SensorColumn::Source::DigitalIn && c.channel >= 0 && c.channel < 16) {
      inputs_.push_back({c.module, c.channel, c.sensor, 0});
      if (c.module >= 0 && c.module < modules) mask_[static_cast<size_t>(c.module)] |= static_cast<uint16_t>(1u << c.channel);
    }
  for (uint16_t& m : mask_)
    if (m == 0) m = 1;   // a module without touch sensors: its input 0
}

std::string TouchEdges::touch_line(int module, unsigned level) {
  return "touch endpoint=" + std::to_string(module) + " level=" + std::to_string(level);
}

}  // namespace chainsim
