// The lockstep barrier, without sockets: which endpoints run at a tick, what
// their TickBegin carries from the bus, and how their TickEnd outputs are
// applied: always in endpoint-index order, whatever order they arrived in.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cosim/bus.h"
#include "chainsim_protocol.h"

namespace chainsim {

// where applied outputs go (the server: the World, the run files, a recorder)
class BarrierSink {
 public:
  virtual ~BarrierSink() = default;
  // servo s of module m: enabled (false = limp) and its set-point as the
  // module sent it, in the actuator's wire unit (the World converts it)
  virtual void servo(int module, int servo, bool enabled, int32_t setpoint_wire) = 0;
  // a bus-log line ("i2c ...", "sync ...", "addr ...")
  virtual void bus_event(int64_t t_us, const char* line) = 0;
  // a log line of endpoint e
  virtual void module_log(int endpoint, int64_t t_us, const char* line) = 0;
  // endpoint e took I2C address `address` (0: gave it up), after its bus-log line
  virtual void address(int endpoint, int64_t t_us, uint8_t address) {
    (void)endpoint, (void)t_us, (void)address;
  }
  // endpoint e sent a frame past its send queue (CS_I2C_TX_QUEUE_MAX bytes
  // waiting on the bus): dropped, after its bus-log line
  virtual void queue_full(int endpoint, int64_t t_us, int queued_bytes) {
    (void)endpoint, (void)t_us, (void)queued_bytes;
  }
};

class Barrier {
 public:
  // modules 0..n_modules-1 with their servo counts; the central control is endpoint n_modules
  Barrier(const std::vector<int>& servo_counts, int64_t tick_us);

  int endpoints() const { return static_cast<int>(ep_.size()); }
  int central() const { return endpoints() - 1; }
  int64_t tick_us() const { return tick_us_; }
  Bus& bus() { return bus_; }
  const Bus& bus() const { return bus_; }

  // deliver due I2C frames, then fill `awake` with the endpoints that run at
  // t_us, in index order, with the reason each woke (CS_WAKE_* bits)
  void due(int64_t t_us, std::vector<int>* awake, BarrierSink* sink);

  // the bus part of e's TickBegin at t_us: Sin level, wake reason, received frames
  void fill_begin(int e, int64_t t_us, cs_tick_begin* tb);

  // store e's TickEnd for this tick; returns an error naming the field if it
  // breaks the rules (wake time not after now, too many set-points)
  std::string store_end(int e, int64_t t_us, const cs_tick_end& te);

  // apply every stored TickEnd in endpoint-index order and clear them
  void apply(int64_t t_us, BarrierSink* sink);

  // endpoint e is off for good (limp mode): never woken, bus sees it unpowered
  void power_off(int e);
  bool powered(int e) const { return ep_[e].powered; }
  uint64_t exchanges(int e) const { return ep_[e].exchanges; }
  // e's I2C address now (0: none) and when it took it (-1: never had one):
  // for a module, discovery's answer
  uint8_t address(int e) const { return ep_[e].addr; }
  int64_t addressed_us(int e) const { return ep_[e].addressed_us; }

 private:
  struct Endpoint {
    int servos = 0;
    bool powered = true;
    int64_t wake_us = 0;
    uint8_t events = 0;
    uint8_t sin_at_sleep = 0;
    uint8_t reason = 0;          // why it woke this tick
    uint8_t sout = 0;
    uint8_t addr = 0;
    int64_t addressed_us = -1;
    uint8_t servo_enable = 0;
    int32_t setpoint[CS_SERVOS_MAX] = {};
    bool fresh = true;           // no output applied yet: apply every servo once
    bool has_end = false;
    cs_tick_end end{};
    uint64_t exchanges = 0;
  };
  int64_t tick_us_;
  std::vector<Endpoint> ep_;
  Bus bus_;
};

}  // namespace chainsim
