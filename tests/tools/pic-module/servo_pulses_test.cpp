// A servo's set-point from the pulses on its pin (tools/pic-module/servo_pulses.h).
#include <gtest/gtest.h>

#include "pic-module/servo_pulses.h"

using chainsim::pic::ServoPulses;

namespace {

// one pulse of width cycles starting at cycle
void pulse(ServoPulses& s, uint64_t at, uint64_t width) {
  s.edge(at, true);
  s.edge(at + width, false);
}

}  // namespace

TEST(ServoPulses, WidthIsTheInverseOfHalPicsPulse) {
  // hal-pic: counts = 7500 + cdeg * 5 / 18; 1 count = 36 millidegrees
  EXPECT_EQ(ServoPulses::wire_from_width(7500), 0);
  EXPECT_EQ(ServoPulses::wire_from_width(10000), 90000);   // 2.0 ms: +90 degrees
  EXPECT_EQ(ServoPulses::wire_from_width(5000), -90000);   // 1.0 ms
  EXPECT_EQ(ServoPulses::wire_from_width(7500 + 833), 29988);  // 3000 cdeg -> 833 counts (truncated) -> 29.988 degrees
}

TEST(ServoPulses, NoPulseYetMeansNotDriven) {
  ServoPulses s;
  EXPECT_FALSE(s.driven(0));
  EXPECT_FALSE(s.driven(1000000));
}

TEST(ServoPulses, TheLatestPulseIsTheSetPointWhilePulsesCome) {
  ServoPulses s;
  pulse(s, 12500, 7500);
  EXPECT_TRUE(s.driven(20000));
  EXPECT_EQ(s.setpoint_wire(), 0);
  pulse(s, 112500, 8333);  // the next 20 ms frame
  EXPECT_EQ(s.setpoint_wire(), 833 * 36);
  EXPECT_TRUE(s.driven(112500 + ServoPulses::kLimpAfterCycles - 1));
  // no more pulses: after two frames the servo goes limp
  EXPECT_FALSE(s.driven(112500 + ServoPulses::kLimpAfterCycles));
  EXPECT_EQ(s.pulses(), 2u);
}

TEST(ServoPulses, GlitchesAreIgnoredAndCounted) {
  ServoPulses s;
  pulse(s, 1000, 7000);
  pulse(s, 101000, 100);     // 20 us: a glitch
  pulse(s, 201000, 20000);   // 4 ms: no servo pulse either
  EXPECT_EQ(s.setpoint_wire(), (7000 - 7500) * 36);
  EXPECT_EQ(s.glitches(), 2u);
  EXPECT_EQ(s.pulses(), 1u);
  // a repeated level is no edge
  s.edge(300000, false);
  EXPECT_EQ(s.glitches(), 2u);
}
