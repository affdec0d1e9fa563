// The rest of the I2C bus as the chip sees it on its SDA and SCL pins, open
// drain with pull-ups: a master that writes the frames the server delivers to
// this module (100 kHz, waiting while the chip stretches the clock), and a
// slave that acknowledges every byte the chip writes as master and hands the
// finished frames to the server. The chip's own MSSP does the rest: its
// address match, its acknowledgements, its clock stretching.
//
// Driven by line changes (lines()) and by its own timer (next_action(),
// act()); after either, the caller puts scl_low() and sda_low() on the pins.
// Pure logic: no gpsim here, so it is tested against a scripted chip.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "chainsim_protocol.h"

namespace chainsim::pic {

class I2cPins {
 public:
  static constexpr uint64_t kNever = UINT64_MAX;
  // half a bit at 100 kHz: 5 us = 25 instruction cycles
  static constexpr uint64_t kHalfBit = 25;
  // a chip that holds SCL low this long has hung the bus (25 ms)
  static constexpr uint64_t kStretchMax = 125000;
  // frames waiting for the bus before new ones are refused
  static constexpr size_t kQueueMax = 64;

  // a frame the server delivered to this module, to write to the chip
  void deliver(const cs_i2c_frame& f);
  // whether the chip holds the clock low after a byte it received (its MSSP
  // stretches SCL until its program has read the byte): asked before each
  // release of SCL after an acknowledge; while true the engine waits
  void set_clock_held(std::function<bool()> held) { clock_held_ = std::move(held); }
  // the lines changed (or may have): their levels on the wire now
  void lines(uint64_t cycle, bool scl, bool sda);
  // the cycle the engine wants act() called at next (kNever: only on a line change)
  uint64_t next_action() const { return next_; }
  void act(uint64_t cycle);

  // whether the engine pulls SCL / SDA low
  bool scl_low() const { return scl_low_; }
  bool sda_low() const { return sda_low_; }
  // frames the chip wrote, finished by their stop, oldest first
  std::vector<cs_i2c_frame> take_sent();
  // what went wrong on the bus since the last call, in words
  std::vector<std::string> take_notes();
  // frames written to the chip and acknowledged to their last byte
  uint64_t delivered() const { return delivered_; }
  // frames waiting for the bus or being written
  size_t waiting() const { return queue_.size(); }
  // frames done with, however they ended (written, refused, dropped)
  uint64_t finished() const { return finished_; }
  bool idle() const { return phase_ == Phase::Idle && queue_.empty() && !slave_; }

 private:
  enum class Phase { Idle, Start, SetBit, Release, WaitHigh, HoldHigh, StopLow, StopRelease, StopWaitHigh,
                     StopHold, BusFree };
  void try_start(uint64_t cycle);
  void abort_master(const std::string& why, bool retry);
  void slave_lines(uint64_t cycle, bool scl_was, bool sda_was);
  void slave_finish();
  uint8_t current_byte() const;

  bool scl_ = true, sda_ = true;   // the lines as last seen
  bool scl_low_ = false, sda_low_ = false;
  uint64_t next_ = kNever;

  // master: the frame being written to the chip
  std::deque<cs_i2c_frame> queue_;
  Phase phase_ = Phase::Idle;
  size_t byte_ = 0;                 // 0 = the address byte
  int bit_ = 0;                     // 0..7 data, 8 = the acknowledge
  bool sent_one_ = false;           // the current bit is a 1 (SDA released)
  uint64_t delivered_ = 0, finished_ = 0;

  // slave: a frame the chip writes
  bool slave_ = false;
  int sbit_ = 0;                    // 0..7 data bits, 8 = acknowledge due, 9 = acknowledging
  unsigned shift_ = 0;
  std::vector<uint8_t> bytes_;
  uint64_t bus_free_at_ = 0;        // the last stop on the bus + the bus free time
  std::vector<cs_i2c_frame> sent_;
  std::vector<std::string> notes_;
  std::function<bool()> clock_held_;
  uint64_t held_since_ = 0;
};

}  // namespace chainsim::pic
