// UART TX decoding. See uart_lines.h.
#include "pic-module/uart_lines.h"

#include <cmath>

namespace chainsim::pic {

UartLines::UartLines(double cycles_per_bit, size_t max_line) : bit_(cycles_per_bit), max_line_(max_line) {}

std::string UartLines::pop_line() {
  std::string l = std::move(lines_.front());
  lines_.pop_front();
  return l;
}

bool UartLines::level_at(uint64_t cycle) const {
  bool level = false;  // the start bit
  for (int i = 0; i < n_edges_ && edge_cycle_[i] <= cycle; ++i) level = edge_level_[i];
  return level;
}

void UartLines::decode() {
  unsigned byte = 0;
  for (int b = 0; b < 8; ++b)  // least significant bit first, sampled mid-bit
    if (level_at(start_ + static_cast<uint64_t>(std::llround((1.5 + b) * bit_)))) byte |= 1u << b;
  const bool stop = level_at(start_ + static_cast<uint64_t>(std::llround(9.5 * bit_)));
  in_frame_ = false;
  n_edges_ = 0;
  if (!stop) {  // a break, or the wrong baud rate
    ++framing_errors_;
    return;
  }
  ++bytes_;
  if (byte == '\n') {
    lines_.push_back(std::move(line_));
    line_.clear();
  } else if (byte != '\r' && line_.size() < max_line_) {
    line_.push_back(byte == 0 ? '?' : static_cast<char>(byte));  // a log line holds no NUL
  }
}

void UartLines::advance(uint64_t cycle) {
  if (in_frame_ && cycle >= start_ + static_cast<uint64_t>(std::llround(9.5 * bit_))) decode();
}

void UartLines::edge(uint64_t cycle, bool high) {
  if (high == level_) return;
  advance(cycle);
  level_ = high;
  if (in_frame_) {
    if (n_edges_ < 24) {
      edge_cycle_[n_edges_] = cycle;
      edge_level_[n_edges_] = high;
      ++n_edges_;
    }
    return;
  }
  if (!high) {  // a start bit
    in_frame_ = true;
    start_ = cycle;
    n_edges_ = 0;
  }
}

}  // namespace chainsim::pic
