// The lockstep barrier. See barrier.h.
#include "cosim/barrier.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

namespace chainsim {

Barrier::Barrier(const std::vector<int>& servo_counts, int64_t tick_us)
    : tick_us_(tick_us), ep_(servo_counts.size() + 1), bus_(static_cast<int>(servo_counts.size()) + 1) {
  for (size_t i = 0; i < servo_counts.size(); ++i) ep_[i].servos = servo_counts[i];
  for (auto& e : ep_) e.reason = CS_WAKE_TIMER;  // everyone runs at t = 0
}

void Barrier::due(int64_t t_us, std::vector<int>* awake, BarrierSink* sink) {
  bus_.deliver_due(
      t_us, [](const BusFrame&, int) {},
      [&](const BusFrame& f, int e) {
        char line[96];
        std::snprintf(line, sizeof line, "i2c-drop from=%d to=0x%02x endpoint=%d inbox full", f.from, f.addr, e);
        sink->bus_event(t_us, line);
      });
  awake->clear();
  for (int e = 0; e < endpoints(); ++e) {
    Endpoint& p = ep_[e];
    if (!p.powered) continue;
    uint8_t why = 0;
    if (t_us >= p.wake_us) why |= CS_WAKE_TIMER;
    if ((p.events & CS_WAKE_I2C) && bus_.has_mail(e)) why |= CS_WAKE_I2C;
    if ((p.events & CS_WAKE_SIN_EDGE) && bus_.sin(e) != p.sin_at_sleep) why |= CS_WAKE_SIN_EDGE;
    if (!why) continue;
    p.reason = why;
    awake->push_back(e);
  }
}

void Barrier::fill_begin(int e, int64_t t_us, cs_tick_begin* tb) {
  tb->time_us = static_cast<uint64_t>(t_us);
  tb->wake_reason = ep_[e].reason;
  tb->sin_level = bus_.sin(e);
  tb->i2c_tx_queued = static_cast<uint16_t>(std::min(bus_.queued_bytes(e), 65535));
  ep_[e].sin_at_sleep = tb->sin_level;  // an edge is a change from what it last saw
  BusFrame frames[CS_I2C_FRAMES_MAX];
  const size_t n = bus_.take_mail(e, frames, CS_I2C_FRAMES_MAX);
  tb->n_i2c = static_cast<uint8_t>(n);
  for (size_t i = 0; i < n; ++i) {
    tb->i2c[i].addr = frames[i].addr;
    tb->i2c[i].len = frames[i].len;
    for (uint8_t k = 0; k < frames[i].len; ++k) tb->i2c[i].data[k] = frames[i].data[k];
  }
  ++ep_[e].exchanges;
}

std::string Barrier::store_end(int e, int64_t t_us, const cs_tick_end& te) {
  Endpoint& p = ep_[e];
  if (te.wake_time_us <= static_cast<uint64_t>(t_us))
    return "asked to wake at " + std::to_string(te.wake_time_us) + " us, which is not after now (" +
           std::to_string(t_us) + " us)";
  if (te.n_servos > p.servos)
    return "sent " + std::to_string(te.n_servos) + " servo set-points but has " +
           std::to_string(p.servos) + " servos";
  p.end = te;
  p.has_end = true;
  return {};
}

void Barrier::apply(int64_t t_us, BarrierSink* sink) {
  char line[160];
  for (int e = 0; e < endpoints(); ++e) {
    Endpoint& p = ep_[e];
    if (!p.has_end) continue;
    p.has_end = false;
    const cs_tick_end& te = p.end;

    for (int s = 0; s < te.n_servos; ++s) {
      const uint8_t bit = static_cast<uint8_t>(1u << s);
      const bool on = te.servo_enable & bit;
      const bool changed = (on != static_cast<bool>(p.servo_enable & bit)) ||
                           (on && te.servo_setpoint[s] != p.setpoint[s]) || p.fresh;
      if (!changed) continue;
      p.servo_enable = static_cast<uint8_t>((p.servo_enable & ~bit) | (on ? bit : 0));
      p.setpoint[s] = te.servo_setpoint[s];
      sink->servo(e, s, on, te.servo_setpoint[s]);
    }
    if (te.sout_level != p.sout) {
      p.sout = te.sout_level;
      bus_.set_sout(e, te.sout_level);
      std::snprintf(line, sizeof line, "sync endpoint=%d sout=%u", e, te.sout_level);
      sink->bus_event(t_us, line);
    }
    if (te.i2c_address != p.addr) {
      p.addr = te.i2c_address;
      p.addressed_us = te.i2c_address != 0 ? t_us : -1;
      bus_.set_address(e, te.i2c_address);
      std::snprintf(line, sizeof line, "addr endpoint=%d address=0x%02x", e, te.i2c_address);
      sink->bus_event(t_us, line);
      sink->address(e, t_us, te.i2c_address);
    }
    for (int i = 0; i < te.n_i2c; ++i) {
      const cs_i2c_frame& f = te.i2c[i];
      const int queued = bus_.queued_bytes(e);
      if (queued + f.len + 1 > static_cast<int>(CS_I2C_TX_QUEUE_MAX)) {  // a flood: as a full MSSP queue
        std::snprintf(line, sizeof line, "i2c-drop from=%d to=0x%02x send queue full (%d bytes waiting)", e, f.addr,
                      queued);
        sink->bus_event(t_us, line);
        sink->queue_full(e, t_us, queued);
        continue;
      }
      const BusFrame& bf = bus_.send(e, f.addr, f.data, f.len, t_us);
      int k = std::snprintf(line, sizeof line, "i2c from=%d to=0x%02x deliver_us=%" PRId64 " data=", e, f.addr,
                            bf.deliver_us);
      for (int b = 0; b < f.len && k < static_cast<int>(sizeof line) - 3; ++b)
        k += std::snprintf(line + k, sizeof line - k, "%02x", f.data[b]);
      sink->bus_event(t_us, line);
    }
    for (int i = 0; i < te.n_log; ++i) sink->module_log(e, t_us, te.log[i]);
    p.fresh = false;

    p.wake_us = static_cast<int64_t>(te.wake_time_us);
    p.events = te.wake_events;
  }
}

void Barrier::power_off(int e) {
  ep_[e].powered = false;
  ep_[e].has_end = false;
  bus_.set_powered(e, false);
}

}  // namespace chainsim
