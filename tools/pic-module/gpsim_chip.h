// One PIC18F2550 in gpsim (Debian's libgpsim): the program loaded from its
// .cod at the board's 20 MHz, its pins joined to lines the module process
// drives and watches, and a run loop that executes instruction cycles until
// a given cycle, an edge on a watched pin, a reset, or execution outside the
// program. gpsim keeps one simulation per process: one chip per process.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pic-module/cpu_meter.h"

class Processor;
class pic_processor;
class Stimulus_Node;

namespace chainsim::pic {

// who hears the edges of the watched pins
class EdgeSink {
 public:
  virtual ~EdgeSink() = default;
  // line `id` changed to `high` during the instruction cycle ending at `cycle`
  virtual void edge(int id, uint64_t cycle, bool high) = 0;
};

class PinLine;

class GpsimChip {
 public:
  enum class Stop { Reached, Edge, Reset, Outside, Overrun };
  // why the chip reset, from its STKPTR and RCON bits
  struct ResetCause {
    std::string what;         // "stack overflow (more than 31 nested calls)", ...
    uint32_t pc = 0;          // the instruction that caused it
    std::vector<uint32_t> calls;  // the return addresses on the hardware stack, outermost first
  };

  // loads cod_path (which names the .hex's code, symbols and assembly
  // lines); throws std::runtime_error when gpsim cannot
  explicit GpsimChip(const std::string& cod_path);
  ~GpsimChip();
  GpsimChip(const GpsimChip&) = delete;
  GpsimChip& operator=(const GpsimChip&) = delete;

  // a line on package pin `pin` (1..28), reported to sink as `id`; with
  // pull_up, a 10 kOhm resistor to 5 V sits on it too (I2C)
  PinLine* line(int pin, int id, EdgeSink* sink, bool pull_up = false);

  // execute until the cycle counter reaches `until`, or stop early at the
  // first edge on a watched line, a reset, execution outside the program or
  // a step over its CPU budget (then pc_at_stop() is where)
  Stop run(uint64_t until, CpuMeter* meter);
  uint64_t cycle() const;
  uint32_t pc_at_stop() const { return last_pc_; }
  // the byte address of the instruction the chip executes next
  uint32_t pc() const;
  ResetCause reset_cause() const;

  // the deepest the hardware return stack has been (of 31)
  int hw_stack_high() const { return hw_high_; }

  // memory, as a programmer or a debugger sees it (no cycle passes)
  uint8_t ram(uint32_t address) const;
  void set_ram(uint32_t address, uint8_t value);
  uint16_t flash_word(uint32_t byte_address) const;
  uint8_t flash_byte(uint32_t byte_address) const;
  bool programmed(uint32_t byte_address) const;
  uint32_t flash_bytes() const;
  void set_eeprom(uint32_t address, uint8_t value);
  // the assembly file and line of the instruction at pc (file empty if unknown)
  void asm_line(uint32_t pc, std::string* file, int* line) const;

 private:
  Processor* cpu_ = nullptr;
  pic_processor* pic_ = nullptr;
  std::vector<std::unique_ptr<PinLine>> lines_;
  std::vector<Stimulus_Node*> nodes_;
  std::vector<std::unique_ptr<class PullUp>> pullups_;
  uint32_t last_pc_ = 0;
  int hw_high_ = 0;
  bool edge_ = false;
  friend class PinLine;
  friend class Source;
};

// One package pin's line: the pin, this stimulus (the world outside the
// chip: a sensor's output, another bus device, an oscilloscope probe) and
// optionally a pull-up, joined in a gpsim node.
class PinLine {
 public:
  ~PinLine();
  // released: high impedance (the chip's output, or the pull-up, decides)
  void release();
  // driven to volts through 100 Ohm (a sensor output, a logic output)
  void drive(double volts);
  void drive_logic(bool high) { drive(high ? 5.0 : 0.0); }
  // the level on the line now
  bool high() const;
  double volts() const;

 private:
  friend class GpsimChip;
  PinLine() = default;
  class Source* src_ = nullptr;
  Stimulus_Node* node_ = nullptr;
};

}  // namespace chainsim::pic
