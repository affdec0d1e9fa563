// The decimal text of numbers: the same bytes as the C library's printf, which
// every output of the server was written with before it had one module.
#include "text/number_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace chainsim {
namespace {

std::string printf_text(const char* fmt, int precision, double v) {
  char b[512];
  std::snprintf(b, sizeof b, fmt, precision, v);
  return b;
}

const std::vector<double>& values() {
  static const std::vector<double> v = {
      0.0, -0.0, 1.0, -1.0, 0.5, 0.125, 2.5, 0.0625, 1e-7, -3.3e-5, 123456.789, 1e15, 1.7976931348623157e308,
      4.9e-324, 0.1 + 0.2, 299.9995, 1.0005, 2.675, -2.675, 1e21, std::nextafter(1.0, 2.0),
      std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  return v;
}

TEST(NumberText, FixedIsPrintfsFixedForEveryPrecision) {
  for (double v : values())
    for (int d = 0; d <= 20; ++d) EXPECT_EQ(fixed_text(v, d), printf_text("%.*f", d, v)) << v << " at " << d;
}

TEST(NumberText, FixedClampsItsDecimals) {
  EXPECT_EQ(fixed_text(2.5, -3), fixed_text(2.5, 0));
  EXPECT_EQ(fixed_text(1.0 / 3.0, 40), fixed_text(1.0 / 3.0, 20));
}

TEST(NumberText, GeneralIsPrintfsGeneral) {
  for (double v : values()) {
    EXPECT_EQ(general_text(v), printf_text("%.*g", 6, v)) << v;
    for (int d = 1; d <= 17; ++d) EXPECT_EQ(general_text(v, d), printf_text("%.*g", d, v)) << v << " at " << d;
  }
  EXPECT_EQ(general_text(0.25), "0.25");
  EXPECT_EQ(general_text(1e-7), "1e-07");
  EXPECT_EQ(general_text(1.0 / 3.0, 40), general_text(1.0 / 3.0, 17));
  EXPECT_EQ(general_text(1234.5, 0), "1e+03");
}

TEST(NumberText, NotANumberIsWrittenAsPrintfWritesIt) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fixed_text(nan, 3), printf_text("%.*f", 3, nan));
  EXPECT_EQ(general_text(nan), printf_text("%.*g", 6, nan));
}

TEST(NumberText, SecondsAreExactMicroseconds) {
  EXPECT_EQ(seconds_text(12000500), "12.000500");
  EXPECT_EQ(seconds_text(0), "0.000000");
  EXPECT_EQ(seconds_text(999999), "0.999999");
  std::string s = "t=";
  append_seconds(&s, 3000001);
  EXPECT_EQ(s, "t=3.000001");
}

}  // namespace
}  // namespace chainsim
