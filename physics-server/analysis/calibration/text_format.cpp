#include "analysis/calibration/text_format.h"

#include <cmath>
#include <cstdio>

namespace chainsim {

std::string fmt_g(double v, int prec) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, std::fabs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

}  // namespace chainsim
