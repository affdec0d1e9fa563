// Encoder pulses on a counter pin (tools/pic-module/pulse_train.h).
#include <gtest/gtest.h>

#include "pic-module/pulse_train.h"

using chainsim::pic::PulseTrain;

namespace {

// run the train until `until`: rising edges counted
int rises(PulseTrain& p, uint64_t until) {
  int n = 0;
  while (p.next_action() < until) {
    const bool was = p.high();
    p.act(p.next_action());
    if (!was && p.high()) ++n;
  }
  return n;
}

}  // namespace

TEST(PulseTrain, TheFirstCountIsWhereTheEncoderStood) {
  PulseTrain p;
  p.tick(1000, 0, 5000);
  EXPECT_EQ(p.next_action(), PulseTrain::kNever);
}

TEST(PulseTrain, ATicksCountsBecomeThatManyPulsesWithinTheTick) {
  PulseTrain p;
  p.tick(0, 0, 5000);
  p.tick(7, 5000, 5000);
  EXPECT_EQ(rises(p, 10000), 7);
  EXPECT_FALSE(p.high());
  EXPECT_EQ(p.sent(), 7u);
  EXPECT_EQ(p.owed(), 0u);
}

TEST(PulseTrain, CountsThatGoDownArePulsesToo) {
  // the board's counters have no direction
  PulseTrain p;
  p.tick(100, 0, 5000);
  p.tick(95, 5000, 5000);
  EXPECT_EQ(rises(p, 10000), 5);
}

TEST(PulseTrain, MoreThanTheTimersTakeFallBehindAndCatchUp) {
  PulseTrain p;
  p.tick(0, 0, 5000);
  p.tick(1000, 5000, 5000);  // 1000 pulses in 1 ms: 10 cycles each is the fastest
  const int first = rises(p, 10000);
  EXPECT_EQ(first, 500);
  EXPECT_EQ(p.owed(), 500u);
  p.tick(1000, 10000, 5000);  // no new counts: the rest go out now
  EXPECT_EQ(rises(p, 20000), 500);
  EXPECT_EQ(p.sent(), 1000u);
}
