// firmware/touch/touch_direction (fw-touch's own): the integer atan2 against the C
// library's, the direction from the switches that closed, and where up is.
#include <gtest/gtest.h>

#include <cmath>

extern "C" {
#include "touch_direction.h"
}

namespace {

TEST(TouchDirection, Atan2WithinAWholeDegree) {
  double worst = 0;
  for (int y = -600; y <= 600; y += 7)
    for (int x = -600; x <= 600; x += 11) {
      if (x == 0 && y == 0) continue;
      double want = std::atan2(y, x) * 180 / M_PI;
      if (want < 0) want += 360;
      const int got = td_atan2_deg(static_cast<int16_t>(y), static_cast<int16_t>(x));
      ASSERT_GE(got, 0);
      ASSERT_LT(got, 360);
      double err = std::fabs(got - want);
      err = std::min(err, 360 - err);
      worst = std::max(worst, err);
    }
  std::printf("worst error %.3f degree\n", worst);
  EXPECT_LE(worst, 0.8);   // the approximation's 0.22, Q10's 0.06 and the rounding to whole degrees
  EXPECT_EQ(td_atan2_deg(0, 0), TD_NONE);
  EXPECT_EQ(td_atan2_deg(0, 100), 0);
  EXPECT_EQ(td_atan2_deg(100, 0), 90);
  EXPECT_EQ(td_atan2_deg(0, -100), 180);
  EXPECT_EQ(td_atan2_deg(-100, 0), 270);
  EXPECT_EQ(td_atan2_deg(32767, 32767), 45);
  EXPECT_EQ(td_atan2_deg(-32768, -32768), 225);
}

TEST(TouchDirection, ThreeSwitchesTellSixDirections) {
  // switch 0 on top, 1 at 120 degrees, 2 at 240
  EXPECT_EQ(td_direction(0b001, 3, 0), 0);
  EXPECT_EQ(td_direction(0b010, 3, 0), 120);
  EXPECT_EQ(td_direction(0b100, 3, 0), 240);
  EXPECT_EQ(td_direction(0b011, 3, 0), 60);
  EXPECT_EQ(td_direction(0b110, 3, 0), 180);
  EXPECT_EQ(td_direction(0b101, 3, 0), 300);
  EXPECT_EQ(td_direction(0b111, 3, 0), TD_NONE);   // head-on
  EXPECT_EQ(td_direction(0, 3, 0), TD_NONE);
  EXPECT_EQ(td_direction(0b001, 3, 90), 90);        // switch 0 on the left
  EXPECT_EQ(td_direction(0b0011, 4, 0), 45);        // four switches, two neighbours
  EXPECT_EQ(td_direction(0b0101, 4, 0), TD_NONE);   // opposite ones balance
}

TEST(TouchDirection, UpFromTheAccelerometerAndTheSides) {
  // 170.7 counts per g about 512
  EXPECT_EQ(td_up_deg(512, 683, 512), 0);      // upright: +z reads +1 g
  EXPECT_EQ(td_up_deg(683, 512, 512), 90);     // rolled: the module's left is up
  EXPECT_EQ(td_up_deg(512, 341, 512), 180);    // upside down
  EXPECT_EQ(td_up_deg(512 + 121, 512 + 121, 512), 45);
  EXPECT_EQ(td_up_deg(520, 500, 512), TD_NONE);  // gravity along the axis (a vertical pipe)
  EXPECT_EQ(td_world_deg(270, 0), 270);
  EXPECT_EQ(td_world_deg(0, 90), 270);         // the module's top faces right when its left is up
  EXPECT_EQ(td_world_deg(TD_NONE, 0), TD_NONE);
  EXPECT_EQ(td_side(0), CC_SIDE_UP);
  EXPECT_EQ(td_side(100), CC_SIDE_LEFT);
  EXPECT_EQ(td_side(200), CC_SIDE_DOWN);
  EXPECT_EQ(td_side(300), CC_SIDE_RIGHT);
  EXPECT_EQ(td_side(TD_NONE), CC_SIDE_NONE);
}

}  // namespace
