// Physics divergence: what the bounds' message says about a body.
#include "physics/divergence.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chainsim {
namespace {

// a body over the speed bound that moves straight down is said to be falling
// (off a terrain's end, out of a pipe), not flung by a blown-up solver
TEST(Divergence, FallingStraightDownIsWithinTenDegreesOfTheVertical) {
  auto at = [](double deg_from_down, double speed) {
    const double a = deg_from_down * 3.14159265358979323846 / 180;
    return falling_straight_down(Eigen::Vector3d(speed * std::sin(a), 0, -speed * std::cos(a)));
  };
  EXPECT_TRUE(at(0, 12));
  EXPECT_TRUE(at(9, 12));
  EXPECT_FALSE(at(11, 12));
  EXPECT_FALSE(at(90, 12));   // sideways
  EXPECT_FALSE(at(180, 12));  // up
  EXPECT_FALSE(at(0, 0));     // at rest
}

}  // namespace
}  // namespace chainsim
