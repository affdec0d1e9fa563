#include "cosim/bus.h"

#include <algorithm>
#include <cstring>

namespace chainsim {

Bus::Bus(int endpoints) : addr_(endpoints, 0), sout_(endpoints, 0), powered_(endpoints, 1), inbox_(endpoints) {}

int64_t Bus::frame_time_us(int len) {
  // start and stop conditions take about one bit time each
  return kBitUs * (2 + 9 * (1 + static_cast<int64_t>(len)));
}

void Bus::set_address(int e, uint8_t addr) { addr_[e] = addr & 0x7F; }

int Bus::queued_bytes(int from) const {
  int n = 0;
  for (const BusFrame& f : in_flight_)
    if (f.from == from) n += f.len + 1;
  return n;
}

const BusFrame& Bus::send(int from, uint8_t addr, const uint8_t* data, uint8_t len, int64_t now_us) {
  BusFrame f;
  f.sent_us = now_us;
  f.from = from;
  f.addr = addr;
  f.len = std::min<uint8_t>(len, static_cast<uint8_t>(f.data.size()));
  std::memcpy(f.data.data(), data, f.len);
  const int64_t start = std::max(now_us, free_at_us_);
  f.deliver_us = start + frame_time_us(f.len);
  free_at_us_ = f.deliver_us;
  in_flight_.push_back(f);
  return in_flight_.back();
}

void Bus::set_powered(int e, bool powered) {
  powered_[e] = powered ? 1 : 0;
  if (!powered) {
    sout_[e] = 0;
    inbox_[e].clear();
  }
}

size_t Bus::take_mail(int e, BusFrame* out, size_t max) {
  size_t n = 0;
  auto& box = inbox_[e];
  while (n < max && !box.empty()) {
    out[n++] = box.front();
    box.pop_front();
  }
  return n;
}

int Bus::predecessor(int e) const {
  const int central = endpoints() - 1;
  if (e == 0) return central;
  if (e == central) return central - 1 >= 0 ? central - 1 : central;
  return e - 1;
}

}  // namespace chainsim
