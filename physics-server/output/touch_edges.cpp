// Touch lines of the bus log. See touch_edges.h.
#include "output/touch_edges.h"

namespace chainsim {

std::string TouchEdges::touch_line(int module, unsigned level) {
  return "touch endpoint=" + std::to_string(module) + " level=" + std::to_string(level);
}

}  // namespace chainsim
