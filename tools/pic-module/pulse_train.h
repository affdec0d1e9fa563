// Encoder pulses on a counter pin: the counts the server's encoder gained in
// a tick, as that many pulses spread evenly over the tick, the way a wheel
// turning at a steady speed makes them. The board's counters see rising
// edges and no direction, so a count that goes down adds pulses too.
#pragma once

#include <cstdint>

namespace chainsim::pic {

class PulseTrain {
 public:
  static constexpr uint64_t kNever = UINT64_MAX;
  // the fastest pulses the board's timers take in (high and low each this
  // long, cycles: 1 us); faster counts fall behind and catch up later
  static constexpr uint64_t kMinHalfPeriod = 5;

  // the encoder's count at the start of the tick [from, from + span)
  void tick(int32_t count, uint64_t from, uint64_t span);
  uint64_t next_action() const { return next_; }
  // the next edge, due at cycle
  void act(uint64_t cycle);
  bool high() const { return high_; }
  // pulses still owed (behind when more came than could be sent)
  uint64_t owed() const { return owed_; }
  uint64_t sent() const { return sent_; }

 private:
  bool started_ = false;
  int32_t last_ = 0;
  bool high_ = false;
  uint64_t owed_ = 0, sent_ = 0;
  uint64_t half_ = kMinHalfPeriod;  // half period of the current tick's pulses
  uint64_t next_ = kNever;
};

}  // namespace chainsim::pic
