// Decimal text of numbers in the run's outputs (trace, logs, messages): the
// one place their formats live, so equal values give equal bytes everywhere.
#pragma once

#include <cstdint>
#include <string>

namespace chainsim {

// integer microseconds as seconds with six decimals, exactly ("12.000500")
void append_seconds(std::string* out, int64_t t_us);
std::string seconds_text(int64_t t_us);

// printf's "%.<decimals>f" (rounding as the C library does)
void append_fixed(std::string* out, double value, int decimals);
std::string fixed_text(double value, int decimals);

}  // namespace chainsim
