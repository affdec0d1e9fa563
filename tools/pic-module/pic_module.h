// The board around the chip: the server's sensor samples put on its pins
// before each tick, the tick's instruction cycles run, and what its pins did
// read back as the module's outputs (docs/pic-in-the-loop.md):
//   servo pulses (RB2..) -> set-points      potentiometers, currents,
//   Sout (RC1) -> Sout                      accelerometer -> ADC voltages (AN0..AN4)
//   UART TX (RC6) -> log lines              Sin -> RC4, touch -> RB6, RB7, RC5, RC2
//   I2C (RB0, RB1) <-> frames, both ways    encoder counts -> pulses on T0CKI, T13CKI, INT2
// The I2C address the server routes frames by is the one the chip's MSSP
// answers to (SSPADD in slave mode); the chip itself decides, at its pins,
// whether it takes a frame.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chainsim_protocol.h"
#include "pic-module/cpu_meter.h"
#include "pic-module/gpsim_chip.h"
#include "pic-module/i2c_pins.h"
#include "pic-module/pic_build.h"
#include "pic-module/pulse_train.h"
#include "pic-module/servo_pulses.h"
#include "pic-module/uart_lines.h"

namespace chainsim::pic {

// CPU seconds of the calling thread
double thread_cpu_s();

struct PicOptions {
  uint64_t budget_us = 0;     // most busy time a step may take (0: no budget)
  bool overrun_warn = false;  // an overrun is a warning on stderr, not a fault
  uint64_t stall_ms = 2000;   // a step busy this long without a wait is a fault
};

class PicModule : public EdgeSink {
 public:
  PicModule(GpsimChip* chip, const PicBuild* build, const PicOptions& options);

  // the scene's parameter values, written to the data EEPROM before the first cycle
  void give_params(const std::map<std::string, int32_t>& values);
  // one tick [tb.time_us, tb.time_us + tick_us): inputs on the pins, the
  // tick's cycles, the outputs into *te. Returns "" or the fault that ends
  // the module (a reset, code outside the program, an overrun, a stall); *te
  // is complete either way (its log lines are the module's last words).
  std::string tick(const cs_tick_begin& tb, uint32_t tick_us, cs_tick_end* te);
  // what the run measured, for summary.json
  nlohmann::json stats() const;
  // the host's side, for the benchmark: CPU seconds in tick() (gpsim's
  // instruction loop is measured inside it) and wall seconds waiting for the
  // server's next TICK_BEGIN
  void host_times(double tick_cpu_s, double server_wait_s) {
    tick_cpu_s_ = tick_cpu_s;
    server_wait_s_ = server_wait_s;
  }
  // the bus's and the bridge's remarks since the last call, for stderr
  std::vector<std::string> take_notes();

  void edge(int id, uint64_t cycle, bool high) override;

 private:
  enum LineId { kServo0 = 0, kSout = 8, kTx, kScl, kSda };
  void wire(const cs_tick_begin& tb);
  void apply_inputs(const cs_tick_begin& tb, uint64_t from, uint64_t span);
  std::string run_until(uint64_t end);
  void drain_edges();
  void drive_i2c();
  std::string where(uint32_t pc);
  std::string fault_at(const std::string& what, uint32_t pc);
  uint8_t address();

  GpsimChip* chip_;
  const PicBuild* build_;
  PicOptions opt_;
  CpuMeter meter_;
  bool wired_ = false;
  int servos_ = 0, adc_ = 0, counters_ = 0;

  std::array<ServoPulses, 4> pulses_;
  std::array<PinLine*, 4> pot_{}, counter_pin_{};
  std::array<PulseTrain, 3> trains_;
  std::array<PinLine*, 5> adc_pin_{};
  std::array<PinLine*, 4> digital_{};
  PinLine *sin_ = nullptr, *sout_ = nullptr, *tx_ = nullptr, *scl_ = nullptr, *sda_ = nullptr;
  UartLines uart_;
  I2cPins i2c_;
  bool scl_level_ = true, sda_level_ = true;   // as the edges told
  bool scl_driven_ = false, sda_driven_ = false;
  struct Edge { int id; uint64_t cycle; bool high; };
  std::vector<Edge> i2c_edges_;
  uint8_t addr_ = 0;
  // a Sin level that waits for this tick's frames (the board flushes its
  // frames before its Sout: on the wire a frame ends before the edge)
  bool sin_level_ = false, sin_pending_ = false;
  uint64_t sin_after_ = 0;  // i2c_.finished() at which it goes on the pin
  std::vector<cs_i2c_frame> out_frames_;        // waiting for a TICK_END with room
  std::vector<std::string> notes_;
  SourceLines source_;
  uint64_t now_us_ = 0;
  uint64_t overrun_warnings_ = 0;
  uint64_t frames_from_chip_ = 0, log_lines_ = 0;
  uint32_t stack_lo_ = 0, stack_hi_ = 0;       // the software stack's RAM, painted
  double gpsim_cpu_s_ = 0, tick_cpu_s_ = 0, server_wait_s_ = 0;
};

}  // namespace chainsim::pic
