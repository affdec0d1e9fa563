// Decimal text of numbers for the server's and tools' outputs and messages
// (trace, logs, reports): the one place these formats live, so equal values
// give equal bytes everywhere. Always the C locale. (Some one-off messages
// still format a number in place with snprintf.)
#pragma once

#include <cstdint>
#include <string>

namespace chainsim {

// integer microseconds as seconds with six decimals, exactly ("12.000500")
void append_seconds(std::string* out, int64_t t_us);
std::string seconds_text(int64_t t_us);

// printf's "%.<decimals>f" (rounding as the C library does); decimals is
// clamped to 0..20
void append_fixed(std::string* out, double value, int decimals);
std::string fixed_text(double value, int decimals);

// printf's "%.<digits>g": the shortest of fixed and exponent forms with that
// many significant digits, trailing zeros dropped ("0.25", "1e-07", "inf"); digits is
// clamped to 1..17
std::string general_text(double value, int digits = 6);

// the shortest decimal text that reads back as exactly this double ("0.1",
// "1e-05", "0.30000000000000004"): for files that are read again (write_scene)
std::string round_trip_text(double value);

}  // namespace chainsim
