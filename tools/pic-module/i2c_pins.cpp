// The bus beside the chip, at its pins. See i2c_pins.h.
#include "pic-module/i2c_pins.h"

#include <cstdio>
#include <utility>

namespace chainsim::pic {

namespace {

std::string hex_addr(unsigned a) {
  char b[8];
  std::snprintf(b, sizeof b, "0x%02X", a);
  return b;
}

}  // namespace

void I2cPins::deliver(const cs_i2c_frame& f) {
  if (queue_.size() >= kQueueMax) {
    notes_.push_back("i2c: a frame to " + hex_addr(f.addr) + " was dropped: " + std::to_string(kQueueMax) +
                     " frames already wait for the bus");
    ++finished_;
    return;
  }
  queue_.push_back(f);
  if (phase_ == Phase::Idle && next_ == kNever) next_ = 0;  // at once, if the bus is free
}

std::vector<cs_i2c_frame> I2cPins::take_sent() { return std::exchange(sent_, {}); }
std::vector<std::string> I2cPins::take_notes() { return std::exchange(notes_, {}); }

uint8_t I2cPins::current_byte() const {
  const cs_i2c_frame& f = queue_.front();
  return byte_ == 0 ? static_cast<uint8_t>(f.addr << 1) : f.data[byte_ - 1];
}

void I2cPins::try_start(uint64_t cycle) {
  if (phase_ != Phase::Idle || queue_.empty() || slave_ || !scl_ || !sda_) return;
  if (cycle < bus_free_at_) {
    next_ = bus_free_at_;
    return;
  }
  sda_low_ = true;  // start: SDA falls while SCL is high
  phase_ = Phase::Start;
  byte_ = 0;
  bit_ = 0;
  next_ = cycle + kHalfBit;
}

void I2cPins::abort_master(const std::string& why, bool retry) {
  notes_.push_back(why);
  if (!retry && !queue_.empty()) {
    queue_.pop_front();
    ++finished_;
  }
  scl_low_ = sda_low_ = false;
  phase_ = Phase::Idle;
  next_ = kNever;
}

void I2cPins::act(uint64_t cycle) {
  if (cycle < next_) return;
  next_ = kNever;
  switch (phase_) {
    case Phase::Idle:
      try_start(cycle);
      break;
    case Phase::Start:
      scl_low_ = true;
      phase_ = Phase::SetBit;
      next_ = cycle + kHalfBit / 2;
      break;
    case Phase::SetBit:
      if (bit_ < 8) {
        sent_one_ = (current_byte() >> (7 - bit_)) & 1u;
        sda_low_ = !sent_one_;
      } else {
        sent_one_ = false;
        sda_low_ = false;  // the chip acknowledges
      }
      phase_ = Phase::Release;
      next_ = cycle + (kHalfBit - kHalfBit / 2);
      break;
    case Phase::Release:
      // after an acknowledge the chip may stretch the clock (bit 0: the
      // next byte's first bit comes)
      if (bit_ == 0 && byte_ > 0 && clock_held_ && clock_held_()) {
        if (!held_since_) held_since_ = cycle;
        if (cycle - held_since_ < kStretchMax) {
          next_ = cycle + 5;
          break;
        }
      }
      held_since_ = 0;
      scl_low_ = false;
      phase_ = Phase::WaitHigh;
      next_ = cycle + kStretchMax;  // the line's rise (lines()) moves on
      break;
    case Phase::WaitHigh:
    case Phase::StopWaitHigh:
      abort_master("i2c: the chip held SCL low for 25 ms; a frame to " + hex_addr(queue_.front().addr) +
                       " was dropped",
                   false);
      break;
    case Phase::HoldHigh: {
      const bool acked = !sda_;
      scl_low_ = true;
      phase_ = Phase::SetBit;
      next_ = cycle + kHalfBit / 2;
      if (bit_ < 8) {
        ++bit_;
        break;
      }
      const cs_i2c_frame& f = queue_.front();
      if (!acked) {
        notes_.push_back("i2c: the chip did not acknowledge " +
                         (byte_ == 0 ? std::string("its address") : "byte " + std::to_string(byte_)) +
                         " of a frame to " + hex_addr(f.addr));
        phase_ = Phase::StopLow;
        byte_ = f.len + 1;  // the frame ends here
        break;
      }
      bit_ = 0;
      if (++byte_ > f.len) phase_ = Phase::StopLow;
      break;
    }
    case Phase::StopLow:
      sda_low_ = true;
      phase_ = Phase::StopRelease;
      next_ = cycle + (kHalfBit - kHalfBit / 2);
      break;
    case Phase::StopRelease:
      if (clock_held_ && clock_held_()) {
        if (!held_since_) held_since_ = cycle;
        if (cycle - held_since_ < kStretchMax) {
          next_ = cycle + 5;
          break;
        }
      }
      held_since_ = 0;
      scl_low_ = false;
      phase_ = Phase::StopWaitHigh;
      next_ = cycle + kStretchMax;
      break;
    case Phase::StopHold:
      sda_low_ = false;  // stop: SDA rises while SCL is high
      if (byte_ == static_cast<size_t>(queue_.front().len) + 1 && bit_ == 0) ++delivered_;
      queue_.pop_front();
      ++finished_;
      phase_ = Phase::BusFree;
      next_ = cycle + kHalfBit;
      break;
    case Phase::BusFree:
      phase_ = Phase::Idle;
      bus_free_at_ = cycle;
      try_start(cycle);
      break;
  }
}

void I2cPins::lines(uint64_t cycle, bool scl, bool sda) {
  const bool scl_was = scl_, sda_was = sda_;
  scl_ = scl;
  sda_ = sda;
  switch (phase_) {
    case Phase::Idle:
      slave_lines(cycle, scl_was, sda_was);
      if (!slave_) try_start(cycle);
      return;
    case Phase::WaitHigh:
      if (scl) {
        phase_ = Phase::HoldHigh;
        next_ = cycle + kHalfBit;
      }
      break;
    case Phase::StopWaitHigh:
      if (scl) {
        phase_ = Phase::StopHold;
        next_ = cycle + kHalfBit;
      }
      break;
    case Phase::HoldHigh:
      // SDA may change while SCL is high only for a start or a stop: not ours
      // means somebody else drives the bus (the chip became a master too)
      if (scl && sda != sda_was && !(bit_ == 8)) {
        abort_master("i2c: lost the bus to the chip in a frame to " + hex_addr(queue_.front().addr) +
                         "; the frame is sent again",
                     true);
        slave_lines(cycle, scl_was, sda_was);
      }
      break;
    default:
      break;
  }
  if (phase_ == Phase::HoldHigh && sent_one_ && bit_ < 8 && scl && !sda) {
    abort_master("i2c: lost arbitration to the chip in a frame to " + hex_addr(queue_.front().addr) +
                     "; the frame is sent again",
                 true);
  }
}

void I2cPins::slave_lines(uint64_t cycle, bool scl_was, bool sda_was) {
  if (scl_ != scl_was) {
    if (!slave_) return;
    if (scl_) {  // rising clock: a data bit is valid
      if (sbit_ < 8) {
        shift_ = (shift_ << 1) | (sda_ ? 1u : 0u);
        ++sbit_;
      }
    } else if (sbit_ == 8) {  // the byte is in: acknowledge it
      bytes_.push_back(static_cast<uint8_t>(shift_ & 0xFFu));
      shift_ = 0;
      sda_low_ = true;
      sbit_ = 9;
    } else if (sbit_ == 9) {  // the acknowledge clock is over
      sda_low_ = false;
      sbit_ = 0;
    }
    return;
  }
  if (sda_ == sda_was || !scl_) return;
  if (!sda_) {  // start, or a repeated start
    if (slave_) slave_finish();
    slave_ = true;
    sbit_ = 0;
    shift_ = 0;
    bytes_.clear();
  } else if (slave_) {  // stop
    slave_finish();
    slave_ = false;
    sda_low_ = false;
    bus_free_at_ = cycle + kHalfBit;
    if (!queue_.empty()) next_ = bus_free_at_;
  }
}

void I2cPins::slave_finish() {
  if (bytes_.empty()) return;
  const unsigned addr_byte = bytes_[0];
  if (addr_byte & 1u) {
    notes_.push_back("i2c: the chip read from " + hex_addr(addr_byte >> 1) +
                     ": the chain protocol has only writes; it got 0xFF");
  } else if (bytes_.size() < 2) {
    notes_.push_back("i2c: the chip wrote a frame with no data to " + hex_addr(addr_byte >> 1));
  } else {
    cs_i2c_frame f{};
    f.addr = static_cast<uint8_t>(addr_byte >> 1);
    size_t n = bytes_.size() - 1;
    if (n > CS_I2C_DATA_MAX) {
      notes_.push_back("i2c: the chip wrote " + std::to_string(n) + " bytes to " + hex_addr(f.addr) +
                       "; a frame holds at most " + std::to_string(CS_I2C_DATA_MAX) + ": the rest is cut");
      n = CS_I2C_DATA_MAX;
    }
    f.len = static_cast<uint8_t>(n);
    for (size_t i = 0; i < n; ++i) f.data[i] = bytes_[i + 1];
    sent_.push_back(f);
  }
  bytes_.clear();
}

}  // namespace chainsim::pic
