// Numbers in the calibration's messages and reports.
#pragma once

#include <string>

namespace chainsim {

// printf "%.*g" with prec significant digits; |v| < 1e-12 prints as 0
std::string fmt_g(double v, int prec = 4);

}  // namespace chainsim
