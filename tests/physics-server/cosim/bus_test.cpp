// The shared I2C bus and the sync-line ring.
#include <gtest/gtest.h>

#include <vector>

#include "cosim/bus.h"

using chainsim::Bus;
using chainsim::BusFrame;

namespace {
struct Delivery {
  int to;
  uint8_t first_byte;
};

std::vector<Delivery> deliver(Bus& bus, int64_t t) {
  std::vector<Delivery> got;
  bus.deliver_due(
      t, [&](const BusFrame& f, int e) { got.push_back({e, f.data[0]}); }, [](const BusFrame&, int) {});
  return got;
}
}  // namespace

TEST(Bus, FrameTakesItsBitTimeAt100kHz) {
  // start + address + 3 data bytes with ACK bits + stop = 2 + 4*9 bits of 10 us
  EXPECT_EQ(Bus::frame_time_us(3), 380);
}

TEST(Bus, FrameIsDeliveredOnlyAfterItsBusTime) {
  Bus bus(3);
  bus.set_address(1, 0x21);
  const uint8_t d[] = {7, 8, 9};
  bus.send(0, 0x21, d, 3, 1000);
  EXPECT_TRUE(deliver(bus, 1379).empty());
  auto got = deliver(bus, 1380);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].to, 1);
  EXPECT_TRUE(bus.has_mail(1));
  EXPECT_FALSE(bus.has_mail(2));
}

TEST(Bus, AddressedFrameReachesOnlyTheMatchingEndpoint) {
  Bus bus(4);
  bus.set_address(0, 0x20);
  bus.set_address(1, 0x21);
  bus.set_address(2, 0x22);
  bus.set_address(3, 0x10);
  const uint8_t d[] = {1};
  bus.send(3, 0x22, d, 1, 0);
  auto got = deliver(bus, 10000);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].to, 2);
}

TEST(Bus, GeneralCallReachesEveryoneButTheSender) {
  Bus bus(4);
  const uint8_t d[] = {5};
  bus.send(3, 0, d, 1, 0);
  auto got = deliver(bus, 10000);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].to, 0);
  EXPECT_EQ(got[1].to, 1);
  EXPECT_EQ(got[2].to, 2);
}

TEST(Bus, FramesSentTogetherAreSerialisedInSendOrder) {
  Bus bus(3);
  bus.set_address(2, 0x10);
  const uint8_t a[] = {1, 1}, b[] = {2, 2};
  const int64_t d1 = bus.send(0, 0x10, a, 2, 0).deliver_us;
  const int64_t d2 = bus.send(1, 0x10, b, 2, 0).deliver_us;
  EXPECT_EQ(d2, d1 + Bus::frame_time_us(2));  // the second waits for the bus
  auto got = deliver(bus, d1);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].first_byte, 1);
  got = deliver(bus, d2);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].first_byte, 2);
}

TEST(Bus, UnpoweredEndpointReceivesNothingAndHoldsSoutLow) {
  Bus bus(3);
  bus.set_sout(1, 1);
  bus.set_powered(1, false);
  EXPECT_EQ(bus.sout(1), 0);
  const uint8_t d[] = {1};
  bus.send(2, 0, d, 1, 0);
  auto got = deliver(bus, 1000);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].to, 0);
}

TEST(Bus, SyncLinesFormARingThroughTheCentralControl) {
  Bus bus(4);  // modules 0,1,2 and the central control 3
  bus.set_sout(3, 1);
  EXPECT_EQ(bus.sin(0), 1);
  EXPECT_EQ(bus.sin(1), 0);
  bus.set_sout(0, 1);
  EXPECT_EQ(bus.sin(1), 1);
  bus.set_sout(2, 1);
  EXPECT_EQ(bus.sin(3), 1);  // the last module closes the ring
}

TEST(Bus, FullInboxDropsAndReports) {
  Bus bus(2);
  const uint8_t d[] = {1};
  for (size_t i = 0; i < Bus::kInboxMax + 3; ++i) bus.send(1, 0, d, 1, 0);
  int drops = 0, delivered = 0;
  bus.deliver_due(
      1 << 30, [&](const BusFrame&, int) { ++delivered; }, [&](const BusFrame&, int) { ++drops; });
  EXPECT_EQ(delivered, static_cast<int>(Bus::kInboxMax));
  EXPECT_EQ(drops, 3);
}
