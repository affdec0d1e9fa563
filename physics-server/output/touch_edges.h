// Bus-log lines for the touch sensors: "touch endpoint=<m> level=<0|1>" each
// time module m's digital input 0 changes (every module starts at 0), so a
// run's bus.log shows when the chain's touch module met something.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "physics/world.h"

namespace chainsim {

class TouchEdges {
 public:
  explicit TouchEdges(int modules) : level_(static_cast<size_t>(modules), 0) {}

  // the line for each module whose input 0 changed since the last call, in
  // module order: line(const char*)
  template <class Line>
  void sample(const World& world, Line line) {
    for (int m = 0; m < static_cast<int>(level_.size()); ++m) {
      const uint8_t level = world.digital_inputs(m) & 1u;
      if (level == level_[m]) continue;
      level_[m] = level;
      line(touch_line(m, level).c_str());
    }
  }

  static std::string touch_line(int module, unsigned level);

 private:
  std::vector<uint8_t> level_;  // last logged level per module
};

}  // namespace chainsim
