// The lockstep barrier: who runs at a tick, and outputs applied in index order.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "cosim/barrier.h"
#include "cosim/bus.h"

using chainsim::Barrier;
using chainsim::BarrierSink;

namespace {

struct Recorder : BarrierSink {
  std::vector<std::string> bus;
  std::vector<std::string> servos;
  std::vector<std::string> logs;
  std::vector<std::pair<int, int>> full;  // (endpoint, bytes waiting) of each queue_full
  void queue_full(int e, int64_t, int queued) override { full.emplace_back(e, queued); }
  void servo(int m, int s, bool on, int32_t setpoint_wire) override {
    servos.push_back(std::to_string(m) + "." + std::to_string(s) +
                     (on ? "=" + std::to_string(setpoint_wire) : "=off"));
  }
  void bus_event(int64_t, const char* line) override { bus.push_back(line); }
  void module_log(int e, int64_t, const char* line) override { logs.push_back(std::to_string(e) + ":" + line); }
};

cs_tick_end sleep_until(uint64_t wake, uint8_t events = 0) {
  cs_tick_end te{};
  te.wake_time_us = wake;
  te.wake_events = events;
  return te;
}

cs_tick_end with_frame(cs_tick_end te, uint8_t to, uint8_t byte) {
  te.i2c[te.n_i2c].addr = to;
  te.i2c[te.n_i2c].len = 1;
  te.i2c[te.n_i2c].data[0] = byte;
  ++te.n_i2c;
  return te;
}

// run one tick at t: wake who is due, then store `ends` in the given order
std::vector<int> tick(Barrier& b, Recorder& r, int64_t t, const std::vector<std::pair<int, cs_tick_end>>& ends) {
  std::vector<int> awake;
  b.due(t, &awake, &r);
  for (int e : awake) {
    cs_tick_begin tb{};
    b.fill_begin(e, t, &tb);
  }
  for (const auto& [e, te] : ends) EXPECT_EQ(b.store_end(e, t, te), "");
  b.apply(t, &r);
  return awake;
}

}  // namespace

TEST(Barrier, EveryEndpointRunsAtTimeZero) {
  Barrier b({2, 2, 2}, 1000);
  Recorder r;
  std::vector<int> awake;
  b.due(0, &awake, &r);
  EXPECT_EQ(awake, (std::vector<int>{0, 1, 2, 3}));
}

TEST(Barrier, OutputsAreAppliedInIndexOrderNotArrivalOrder) {
  Barrier b({0, 0, 0}, 1000);
  Recorder r;
  // replies arrive 2, 0, 3, 1; each sends a frame and a log line
  tick(b, r, 0,
       {{2, with_frame(sleep_until(1000), 0x10, 2)},
        {0, with_frame(sleep_until(1000), 0x10, 0)},
        {3, sleep_until(1000)},
        {1, with_frame(sleep_until(1000), 0x10, 1)}});
  // the bus serialises them in that order: each 1-byte frame takes
  // 10 us x (2 + 9 x 2) = 200 us after the one before
  EXPECT_EQ(r.bus, (std::vector<std::string>{"i2c from=0 to=0x10 deliver_us=200 data=00",
                                             "i2c from=1 to=0x10 deliver_us=400 data=01",
                                             "i2c from=2 to=0x10 deliver_us=600 data=02"}));
}

TEST(Barrier, SleepingModuleIsNotWokenBeforeItsTime) {
  Barrier b({1, 1}, 1000);
  Recorder r;
  tick(b, r, 0, {{0, sleep_until(5000)}, {1, sleep_until(1000)}, {2, sleep_until(1000)}});
  for (int64_t t = 1000; t < 5000; t += 1000) {
    auto awake = tick(b, r, t, {{1, sleep_until(t + 1000)}, {2, sleep_until(t + 1000)}});
    EXPECT_EQ(awake, (std::vector<int>{1, 2})) << "t=" << t;
  }
  std::vector<int> awake;
  b.due(5000, &awake, &r);
  EXPECT_EQ(awake, (std::vector<int>{0, 1, 2}));
  cs_tick_begin tb{};
  b.fill_begin(0, 5000, &tb);
  EXPECT_EQ(tb.wake_reason, CS_WAKE_TIMER);
}

TEST(Barrier, I2cFrameForASleeperWakesItOnlyIfItAskedAndOnlyForItsAddress) {
  Barrier b({0, 0}, 1000);  // modules 0, 1; central 2
  Recorder r;
  cs_tick_end m0 = sleep_until(1000000, CS_WAKE_I2C);
  m0.i2c_address = 0x20;
  cs_tick_end m1 = sleep_until(1000000, 0);  // no events asked
  m1.i2c_address = 0x21;
  tick(b, r, 0, {{0, m0}, {1, m1}, {2, with_frame(sleep_until(1000), 0x21, 9)}});
  // a frame for module 1 (which did not ask) wakes nobody
  auto awake = tick(b, r, 1000, {{2, with_frame(sleep_until(2000), 0x20, 7)}});
  EXPECT_EQ(awake, (std::vector<int>{2}));
  // next tick the frame for module 0 has crossed the bus: module 0 wakes, with its frame
  std::vector<int> a2;
  b.due(2000, &a2, &r);
  EXPECT_EQ(a2, (std::vector<int>{0, 2}));
  cs_tick_begin tb{};
  b.fill_begin(0, 2000, &tb);
  EXPECT_EQ(tb.wake_reason, CS_WAKE_I2C);
  ASSERT_EQ(tb.n_i2c, 1);
  EXPECT_EQ(tb.i2c[0].data[0], 7);
  EXPECT_EQ(tb.i2c[0].addr, 0x20);
}

TEST(Barrier, SinEdgeWakesANeighbourThatAskedForIt) {
  Barrier b({0, 0}, 1000);
  Recorder r;
  tick(b, r, 0, {{0, sleep_until(1000000, CS_WAKE_SIN_EDGE)}, {1, sleep_until(1000000, CS_WAKE_SIN_EDGE)},
                 {2, sleep_until(1000)}});
  cs_tick_end central = sleep_until(2000);
  central.sout_level = 1;  // central's Sout drives module 0's Sin
  tick(b, r, 1000, {{2, central}});
  std::vector<int> awake;
  b.due(2000, &awake, &r);
  EXPECT_EQ(awake, (std::vector<int>{0, 2}));  // module 1's Sin did not change
  cs_tick_begin tb{};
  b.fill_begin(0, 2000, &tb);
  EXPECT_EQ(tb.wake_reason, CS_WAKE_SIN_EDGE);
  EXPECT_EQ(tb.sin_level, 1);
}

TEST(Barrier, RejectsAWakeTimeThatIsNotInTheFuture) {
  Barrier b({2}, 1000);
  std::vector<int> awake;
  Recorder r;
  b.due(0, &awake, &r);
  EXPECT_EQ(b.store_end(0, 0, sleep_until(0)), "asked to wake at 0 us, which is not after now (0 us)");
  EXPECT_EQ(b.store_end(0, 0, sleep_until(1)), "");
}

TEST(Barrier, RejectsMoreSetPointsThanTheModuleHasServos) {
  Barrier b({2}, 1000);
  cs_tick_end te = sleep_until(1000);
  te.n_servos = 3;
  EXPECT_EQ(b.store_end(0, 0, te), "sent 3 servo set-points but has 2 servos");
  te.n_servos = 2;
  EXPECT_EQ(b.store_end(0, 0, te), "");
}

TEST(Barrier, ServoCommandsAreAppliedOnceThenOnlyWhenTheyChange) {
  Barrier b({2}, 1000);
  Recorder r;
  cs_tick_end te = sleep_until(1000);
  te.n_servos = 2;
  te.servo_enable = 0x1;
  te.servo_setpoint[0] = 90000;  // 90 degrees in millidegrees: passed on as sent
  tick(b, r, 0, {{0, te}, {1, sleep_until(1000)}});
  // both servos stated once: one driven, one limp
  EXPECT_EQ(r.servos, (std::vector<std::string>{"0.0=90000", "0.1=off"}));
  te.wake_time_us = 2000;
  tick(b, r, 1000, {{0, te}, {1, sleep_until(2000)}});
  EXPECT_EQ(r.servos.size(), 2u);  // unchanged: nothing applied
  te.servo_setpoint[0] = -45000;
  te.wake_time_us = 3000;
  tick(b, r, 2000, {{0, te}, {1, sleep_until(3000)}});
  ASSERT_EQ(r.servos.size(), 3u);
  EXPECT_EQ(r.servos[2], "0.0=-45000");
}

TEST(Barrier, PoweredOffEndpointNeverRunsAgain) {
  Barrier b({0, 0}, 1000);
  Recorder r;
  b.power_off(1);
  auto awake = tick(b, r, 0, {{0, sleep_until(1000)}, {2, sleep_until(1000)}});
  EXPECT_EQ(awake, (std::vector<int>{0, 2}));
  awake = tick(b, r, 1000, {});
  EXPECT_EQ(awake, (std::vector<int>{0, 2}));
}

// a module that sends faster than the 100 kHz bus carries fills its send
// queue: TICK_BEGIN tells it how much of its own is still on the bus, and a
// frame past CS_I2C_TX_QUEUE_MAX is dropped and reported, the bus backlog
// bounded; frames of the others still go out
TEST(Barrier, AFloodFillsTheSendersQueueAndIsDroppedPastIt) {
  Barrier b({2, 2}, 1000);
  Recorder r;
  cs_tick_end flood = sleep_until(1);
  flood.n_i2c = CS_I2C_FRAMES_MAX;
  for (unsigned i = 0; i < CS_I2C_FRAMES_MAX; ++i) {
    flood.i2c[i].addr = 0x20;
    flood.i2c[i].len = CS_I2C_DATA_MAX;
  }
  int64_t max_backlog = 0;
  uint16_t told = 0;
  for (int64_t t = 0; t < 50000; t += 1000) {
    std::vector<int> awake;
    b.due(t, &awake, &r);
    for (int e : awake) {
      cs_tick_begin tb{};
      b.fill_begin(e, t, &tb);
      if (e == 0) told = std::max(told, tb.i2c_tx_queued);
    }
    flood.wake_time_us = static_cast<uint64_t>(t + 1000);
    EXPECT_EQ(b.store_end(0, t, flood), "");
    EXPECT_EQ(b.store_end(1, t, with_frame(sleep_until(static_cast<uint64_t>(t + 1000)), 0x21, 7)), "");
    b.apply(t, &r);
    for (const auto& line : r.bus) {
      const size_t at = line.find("deliver_us=");
      if (at != std::string::npos) max_backlog = std::max<int64_t>(max_backlog, std::stoll(line.substr(at + 11)) - t);
    }
    r.bus.clear();
  }
  // the first drop is reported; the queue never holds more than its bound
  ASSERT_FALSE(r.full.empty());
  EXPECT_EQ(r.full[0].first, 0);
  EXPECT_LE(r.full[0].second + 33, static_cast<int>(CS_I2C_TX_QUEUE_MAX) + 33);
  EXPECT_GT(told, CS_I2C_TX_QUEUE_MAX - 2 * 33u);  // the module was told its queue was nearly full
  EXPECT_LE(told, CS_I2C_TX_QUEUE_MAX);
  // 512 bytes of one sender (16 frames of 32) and a frame of the other: some
  // 50 ms of bus time ahead at most; unbounded, 50 ticks of 8 frames were 1.2 s
  EXPECT_LT(max_backlog, 20 * chainsim::Bus::frame_time_us(CS_I2C_DATA_MAX));
}
