// fast_tanh (physics/actuators/fast_tanh.h): how far it is from the exact
// tanh, and its exact values (zeros, saturation, NaN, symmetry).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>

#include "physics/actuators/fast_tanh.h"

using chainsim::fast_tanh;

// against long double's tanhl (64-bit mantissa: the exact tanh to well
// within the ulp of a double), in units of the double's ulp at the result
TEST(FastTanh, IsWithin3UlpOfTheExactTanhOverTwentyMillionArguments) {
  std::mt19937_64 g(20261130);
  std::uniform_real_distribution<double> wide(-25.0, 25.0), unit(-1.0, 1.0), mid(0.5, 1.0);
  double worst = 0.0, worst_at = 0.0;
  for (int i = 0; i < 20000000; ++i) {
    double x;
    switch (i % 4) {
      case 0: x = wide(g); break;
      case 1: x = unit(g); break;
      case 2: x = std::ldexp(mid(g), -static_cast<int>(g() % 60)) * (g() % 2 ? 1.0 : -1.0); break;
      default: x = 20.0 * unit(g) * unit(g); break;   // the friction's rates / ws, mostly near rest
    }
    const long double want = tanhl(static_cast<long double>(x));
    const double got = fast_tanh(x);
    const double near = static_cast<double>(fabsl(want));
    const double ulp = std::nextafter(near, 2.0) - near;
    const double err = static_cast<double>(fabsl(static_cast<long double>(got) - want)) / ulp;
    if (err > worst) worst = err, worst_at = x;
    ASSERT_LE(std::fabs(got), 1.0) << x;
    ASSERT_TRUE(got == 0.0 || std::signbit(got) == std::signbit(x)) << x;
  }
  std::printf("[ fast_tanh ] worst %.2f ulp at %.17g\n", worst, worst_at);
  EXPECT_LE(worst, 3.0) << "at " << worst_at;
}

TEST(FastTanh, IsOdd) {
  for (int k = 0; k <= 200000; ++k) {
    const double x = k * 1e-4;   // 0 .. 20
    EXPECT_EQ(std::bit_cast<uint64_t>(fast_tanh(-x)), std::bit_cast<uint64_t>(-fast_tanh(x))) << x;
  }
}

TEST(FastTanh, GivesTheExactValuesAtZeroAtSaturationAndForNan) {
  EXPECT_EQ(std::bit_cast<uint64_t>(fast_tanh(0.0)), std::bit_cast<uint64_t>(0.0));
  EXPECT_EQ(std::bit_cast<uint64_t>(fast_tanh(-0.0)), std::bit_cast<uint64_t>(-0.0));
  for (double x : {19.1, 20.0, 21.5, 700.0, 1e300, std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(fast_tanh(x), 1.0) << x;
    EXPECT_EQ(fast_tanh(-x), -1.0) << x;
  }
  EXPECT_TRUE(std::isnan(fast_tanh(std::numeric_limits<double>::quiet_NaN())));
  // just below saturation it is below 1, as tanh is
  EXPECT_LT(fast_tanh(18.0), 1.0);
  EXPECT_EQ(fast_tanh(18.0), static_cast<double>(tanhl(18.0L)));
}
