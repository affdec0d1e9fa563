// The chain's shared I2C bus and its Sin/Sout synchronism lines.
//
// Endpoints are the modules 0..N-1 and the central control N. I2C frames are
// serialised on one 100 kHz bus in the order they are sent (the server sends
// in module-index order) and delivered after their bus time to every endpoint
// whose address matches, or to all for the general call; never to the sender.
// The sync lines form a ring: central Sout -> module 0 Sin, module k Sout ->
// module k+1 Sin, module N-1 Sout -> central Sin.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace chainsim {

struct BusFrame {
  int64_t sent_us = 0;     // when the sender handed it to the bus
  int64_t deliver_us = 0;  // when its last bit has left the bus
  int from = 0;            // endpoint index of the sender
  uint8_t addr = 0;        // 7-bit destination, 0 = general call
  uint8_t len = 0;
  std::array<uint8_t, 32> data{};
};

class Bus {
 public:
  static constexpr int64_t kBitUs = 10;          // 100 kHz
  static constexpr size_t kInboxMax = 64;        // frames waiting per endpoint

  explicit Bus(int endpoints);

  int endpoints() const { return static_cast<int>(addr_.size()); }

  // microseconds a frame of len data bytes occupies the bus:
  // start + address byte + data bytes (9 bits each with ACK) + stop
  static int64_t frame_time_us(int len);

  // the 7-bit address endpoint e answers to (0 = general call only)
  void set_address(int e, uint8_t addr);
  uint8_t address(int e) const { return addr_[e]; }

  // bytes (address + data) of endpoint from's frames not yet delivered: its
  // send queue, as the board's MSSP would hold them
  int queued_bytes(int from) const;

  // put a frame on the bus at time now_us; returns the queued frame
  const BusFrame& send(int from, uint8_t addr, const uint8_t* data, uint8_t len, int64_t now_us);

  // move frames whose bus time has passed by now_us into the inboxes of their
  // receivers; calls on_deliver(frame, receiver) for each delivery and
  // on_drop(frame, receiver) when a receiver's inbox is full
  template <class Deliver, class Drop>
  void deliver_due(int64_t now_us, Deliver on_deliver, Drop on_drop);

  // a powered-off endpoint receives nothing and drives its Sout low
  void set_powered(int e, bool powered);

  bool has_mail(int e) const { return !inbox_[e].empty(); }
  // take up to max frames for endpoint e, oldest first
  size_t take_mail(int e, BusFrame* out, size_t max);

  // sync lines
  void set_sout(int e, uint8_t level) { sout_[e] = level ? 1 : 0; }
  uint8_t sout(int e) const { return sout_[e]; }
  uint8_t sin(int e) const { return sout_[predecessor(e)]; }
  int predecessor(int e) const;

 private:
  std::vector<uint8_t> addr_;
  std::vector<uint8_t> sout_;
  std::vector<uint8_t> powered_;
  std::deque<BusFrame> in_flight_;
  std::vector<std::deque<BusFrame>> inbox_;
  int64_t free_at_us_ = 0;  // when the bus is idle again
};

template <class Deliver, class Drop>
void Bus::deliver_due(int64_t now_us, Deliver on_deliver, Drop on_drop) {
  while (!in_flight_.empty() && in_flight_.front().deliver_us <= now_us) {
    const BusFrame f = in_flight_.front();
    in_flight_.pop_front();
    for (int e = 0; e < endpoints(); ++e) {
      if (e == f.from || !powered_[e]) continue;
      if (f.addr != 0 && f.addr != addr_[e]) continue;
      if (inbox_[e].size() >= kInboxMax) {
        on_drop(f, e);
        continue;
      }
      inbox_[e].push_back(f);
      on_deliver(f, e);
    }
  }
}

}  // namespace chainsim
