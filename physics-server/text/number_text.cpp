// Decimal text of numbers. See number_text.h.
#include "text/number_text.h"

#include <charconv>
#include <cinttypes>
#include <cstdio>

namespace chainsim {

void append_seconds(std::string* out, int64_t t_us) {
  char buf[32];
  const int n = std::snprintf(buf, sizeof buf, "%" PRId64 ".%06" PRId64, t_us / 1000000, t_us % 1000000);
  out->append(buf, static_cast<size_t>(n));
}

std::string seconds_text(int64_t t_us) {
  std::string s;
  append_seconds(&s, t_us);
  return s;
}

// std::to_chars with a precision writes what printf's "%.Nf" writes in the
// C locale (both exactly rounded), several times faster: the trace's numbers
void append_fixed(std::string* out, double value, int decimals) {
  char buf[352];  // "%.Nf" of the largest double with N <= 20 fits
  if (decimals < 0) decimals = 0;
  if (decimals > 20) decimals = 20;
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
  out->append(buf, r.ptr);
}

std::string fixed_text(double value, int decimals) {
  std::string s;
  append_fixed(&s, value, decimals);
  return s;
}

std::string round_trip_text(double value) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);  // shortest; the C locale by definition
  return std::string(buf, r.ptr);
}

std::string general_text(double value, int digits) {
  char buf[64];  // "-d.<16 digits>e-308" at most
  if (digits < 1) digits = 1;
  if (digits > 17) digits = 17;
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

}  // namespace chainsim
