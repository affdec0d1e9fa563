// Log lines read from the chip's UART TX pin: 8N1 frames decoded from the
// pin's edges (each sampled in the middle of its bit), bytes gathered into
// lines ended by LF (CR dropped), as a terminal on the board's serial port
// would show them.
#pragma once

#include <cstdint>
#include <deque>
#include <string>

namespace chainsim::pic {

class UartLines {
 public:
  // cycles_per_bit: instruction cycles per bit at the receiver's baud rate;
  // max_line: characters kept of a line (the rest is dropped and counted)
  UartLines(double cycles_per_bit, size_t max_line);

  // the TX pin went high or low at cycle (idle is high)
  void edge(uint64_t cycle, bool high);
  // decode a frame whose stop bit has passed by cycle (call at the end of
  // every stretch of cycles: a frame's last edge may be long before)
  void advance(uint64_t cycle);

  // complete lines, oldest first; take them with pop
  bool has_line() const { return !lines_.empty(); }
  std::string pop_line();
  size_t lines_waiting() const { return lines_.size(); }
  uint64_t framing_errors() const { return framing_errors_; }
  uint64_t bytes() const { return bytes_; }

 private:
  bool level_at(uint64_t cycle) const;
  void decode();

  double bit_;
  size_t max_line_;
  bool level_ = true;        // the line now
  bool in_frame_ = false;
  uint64_t start_ = 0;       // the start bit's falling edge
  // the frame's edges after its start: (cycle, new level)
  uint64_t edge_cycle_[24];
  bool edge_level_[24];
  int n_edges_ = 0;
  std::string line_;
  std::deque<std::string> lines_;
  uint64_t framing_errors_ = 0, bytes_ = 0;
};

}  // namespace chainsim::pic
