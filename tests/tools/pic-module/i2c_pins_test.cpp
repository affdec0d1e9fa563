// The bus beside the chip, at its pins (tools/pic-module/i2c_pins.h), against
// a scripted chip: a slave that acknowledges (or not) and stretches the
// clock, and a master that writes a frame at 100 kHz. The wire is open
// drain: a line is low when either side pulls it low.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "pic-module/i2c_pins.h"

using chainsim::pic::I2cPins;

namespace {

cs_i2c_frame frame(uint8_t addr, std::vector<uint8_t> data) {
  cs_i2c_frame f{};
  f.addr = addr;
  f.len = static_cast<uint8_t>(data.size());
  std::memcpy(f.data, data.data(), data.size());
  return f;
}

struct Wire {
  I2cPins eng;
  bool chip_scl = false, chip_sda = false;  // the chip pulls low
  bool scl_seen = true, sda_seen = true;     // what the engine was told last
  uint64_t now = 0;
  bool scl() const { return !(eng.scl_low() || chip_scl); }
  bool sda() const { return !(eng.sda_low() || chip_sda); }
  // the engine hears every change, its own included, until the lines are still
  void settle() {
    for (int i = 0; i < 16 && (scl() != scl_seen || sda() != sda_seen); ++i) {
      scl_seen = scl();
      sda_seen = sda();
      eng.lines(now, scl_seen, sda_seen);
    }
  }
  void engine_acts() {
    if (eng.next_action() <= now) {
      eng.act(now);
      settle();
    }
  }
};

// a slave chip: samples SDA at rising SCL, acknowledges after 8 bits when
// `ack` says so, may hold SCL low for `stretch` cycles after each byte
struct SlaveChip {
  explicit SlaveChip(Wire* wire) : w(wire) {}
  Wire* w;
  bool ack_address = true;
  uint64_t stretch = 0;
  bool last_scl = true, last_sda = true, in_frame = false;
  int bits = 0;
  unsigned shift = 0;
  bool acking = false, first_byte = false;
  uint64_t release_scl_at = 0;
  std::vector<uint8_t> got;
  int starts = 0, stops = 0;
  void step() {
    const bool scl = w->scl(), sda = w->sda();
    if (w->chip_scl && w->now >= release_scl_at) {
      w->chip_scl = false;
      w->settle();
      return;
    }
    if (scl && last_scl && sda != last_sda) {
      if (!sda) { in_frame = true; bits = 0; shift = 0; ++starts; first_byte = true; }
      else { in_frame = false; ++stops; }
    } else if (in_frame && scl && !last_scl && bits < 8) {
      shift = (shift << 1) | (sda ? 1u : 0u);
      ++bits;
    } else if (in_frame && !scl && last_scl) {
      if (bits == 8 && !acking) {
        got.push_back(static_cast<uint8_t>(shift));
        acking = !first_byte || ack_address;
        first_byte = false;
        if (acking) w->chip_sda = true;
        bits = 9;
        if (stretch) {
          w->chip_scl = true;
          release_scl_at = w->now + stretch;
        }
      } else if (bits == 9) {
        w->chip_sda = false;
        acking = false;
        bits = 0;
        shift = 0;
      }
    }
    last_scl = scl;
    last_sda = sda;
    w->settle();
    last_scl = w->scl();
    last_sda = w->sda();
  }
};

uint64_t run_until_idle(Wire& w, SlaveChip* chip, uint64_t limit) {
  const uint64_t start = w.now;
  for (; w.now < start + limit; ++w.now) {
    w.engine_acts();
    if (chip) chip->step();
    if (w.eng.idle() && w.now > start + 10) break;
  }
  return w.now - start;
}

}  // namespace

TEST(I2cPins, WritesAFrameToTheChipBitByBitAt100kHz) {
  Wire w;
  SlaveChip chip(&w);
  w.eng.deliver(frame(0x20, {0x10, 0x01, 0xFF}));
  const uint64_t took = run_until_idle(w, &chip, 100000);
  EXPECT_EQ(chip.got, (std::vector<uint8_t>{0x40, 0x10, 0x01, 0xFF}));
  EXPECT_EQ(chip.starts, 1);
  EXPECT_EQ(chip.stops, 1);
  EXPECT_EQ(w.eng.delivered(), 1u);
  EXPECT_EQ(w.eng.finished(), 1u);
  // the server's bus model: 10 us x (2 + 9 x (1 + 3 bytes)) = 380 us = 1900 cycles
  EXPECT_NEAR(static_cast<double>(took), 1900.0, 60.0);
  EXPECT_TRUE(w.eng.take_notes().empty());
}

TEST(I2cPins, WaitsWhileTheChipStretchesTheClock) {
  Wire w;
  SlaveChip chip(&w);
  chip.stretch = 3000;  // the chip's interrupt takes 600 us to read each byte
  w.eng.deliver(frame(0x21, {0xAA, 0x55}));
  w.eng.deliver(frame(0x00, {0x11}));
  const uint64_t took = run_until_idle(w, &chip, 200000);
  EXPECT_EQ(chip.got, (std::vector<uint8_t>{0x42, 0xAA, 0x55, 0x00, 0x11}));
  EXPECT_EQ(w.eng.delivered(), 2u);
  EXPECT_GT(took, 5u * 3000u);
}

TEST(I2cPins, AFrameTheChipDoesNotAcknowledgeEndsAtItsAddressAndIsNamed) {
  Wire w;
  SlaveChip chip(&w);
  chip.ack_address = false;
  w.eng.deliver(frame(0x33, {0x01, 0x02}));
  run_until_idle(w, &chip, 100000);
  EXPECT_EQ(chip.got, (std::vector<uint8_t>{0x66}));  // nothing after the address
  EXPECT_EQ(chip.stops, 1);                           // but a stop
  EXPECT_EQ(w.eng.delivered(), 0u);
  EXPECT_EQ(w.eng.finished(), 1u);
  const auto notes = w.eng.take_notes();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], "i2c: the chip did not acknowledge its address of a frame to 0x33");
}

TEST(I2cPins, AChipThatHoldsTheClockForeverLosesTheFrameWithANote) {
  Wire w;
  w.eng.deliver(frame(0x20, {0x01}));
  w.chip_scl = true;  // the chip pulls SCL low and never lets go
  w.settle();
  run_until_idle(w, nullptr, 10);
  EXPECT_EQ(w.eng.next_action(), I2cPins::kNever) << "the bus is busy: it waits for a free bus";
  // free the bus: the engine starts, then the chip holds the clock
  w.chip_scl = false;
  w.settle();
  for (int i = 0; i < 40; ++i, ++w.now) w.engine_acts();
  w.chip_scl = true;
  w.settle();
  run_until_idle(w, nullptr, I2cPins::kStretchMax + 100);
  EXPECT_EQ(w.eng.finished(), 1u);
  const auto notes = w.eng.take_notes();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("held SCL low for 25 ms"), std::string::npos) << notes[0];
}

TEST(I2cPins, AcknowledgesEveryByteTheChipWritesAndHandsOverTheFrameAtItsStop) {
  Wire w;
  const std::vector<uint8_t> bytes{static_cast<uint8_t>(0x10 << 1), 0x02, 0x20, 0x01};
  std::vector<bool> acked;
  auto half = [&](int n) {
    for (int i = 0; i < n * 25; ++i, ++w.now) w.engine_acts();
  };
  // a frame queued for the chip meanwhile waits for the chip's stop
  w.chip_sda = true;  // start
  w.settle();
  w.eng.deliver(frame(0x40, {0x99}));
  half(1);
  for (uint8_t b : bytes) {
    for (int bit = 7; bit >= -1; --bit) {
      w.chip_scl = true;
      w.settle();
      half(1);
      w.chip_sda = bit >= 0 && !((b >> bit) & 1u);  // bit -1: the acknowledge slot, released
      w.settle();
      half(1);
      w.chip_scl = false;
      w.settle();
      half(1);
      if (bit < 0) acked.push_back(!w.sda());
    }
  }
  w.chip_scl = true;  // stop: SDA rises while SCL is high
  w.chip_sda = true;
  w.settle();
  half(1);
  w.chip_scl = false;
  w.settle();
  half(1);
  w.chip_sda = false;
  w.settle();
  EXPECT_EQ(acked, std::vector<bool>(4, true));
  const auto sent = w.eng.take_sent();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].addr, 0x10);
  EXPECT_EQ(std::vector<uint8_t>(sent[0].data, sent[0].data + sent[0].len), (std::vector<uint8_t>{0x02, 0x20, 0x01}));
  EXPECT_EQ(w.eng.delivered(), 0u) << "the queued frame waited";
  // after the stop and the bus free time it goes out (no chip answers: not acknowledged)
  SlaveChip none(&w);
  none.ack_address = false;
  run_until_idle(w, &none, 100000);
  EXPECT_EQ(w.eng.finished(), 1u);
}
