// How busy the chip's program is, from where its program counter is, cycle
// by cycle. A step of the program runs from one call of a HAL wait
// (hal_tick_wait, hal_delay_ms, hal_wait_event_ms) to the next; its busy
// cycles are those its main line is at work: from the wait's return to the
// next wait's first pass through the idle loop (hal-pic's next_tick), the
// wait's flush of the outputs and the interrupts that cut in included, as
// they delay it on the board. From that first pass until the wait returns,
// everything at the wait's depth of the hardware return stack or deeper
// (the wait's own polling, the interrupts) idles. The load counts every
// cycle outside the idle loop. Also where the program counter must never
// be: outside the program's code.
#pragma once

#include <cstdint>
#include <vector>

#include "pic-module/pic_build.h"

namespace chainsim::pic {

struct CpuStats {
  uint64_t steps = 0;             // complete steps (wait to wait)
  uint64_t startup_cycles = 0;    // from reset to the first wait
  uint64_t busy_sum = 0;          // busy cycles of the complete steps' main line
  uint64_t busy_worst = 0;
  uint64_t worst_at = 0;          // the cycle the worst step began at
  uint64_t period_sum = 0;        // cycles of the complete steps
  uint64_t busy_total = 0;        // every cycle outside the idle loop (interrupts included): the load
  uint64_t cycles = 0;            // every cycle metered
  uint64_t overruns = 0;          // steps over the budget
};

class CpuMeter {
 public:
  enum : uint8_t { kIdle = 1, kWaitEntry = 2, kOutside = 4, kOverrun = 8 };

  // flags of every instruction word of the program memory (kIdle inside the
  // idle loop, kWaitEntry at a wait's first instruction, kOutside where the
  // build put no code)
  explicit CpuMeter(std::vector<uint8_t> word_flags) : flags_(std::move(word_flags)) {}
  // the flags for a build: its idle loop and waits from the map; programmed
  // words from the loaded program memory (programmed(byte address))
  template <class Programmed>
  static std::vector<uint8_t> flags_for(const PicBuild& b, uint32_t flash_bytes, Programmed programmed);
  // whether the map told where the waits and the idle loop are
  bool metering() const { return metering_; }
  void set_metering(bool on) { metering_ = on; }

  // a step over this many busy cycles is an overrun (0: no budget)
  void set_budget(uint64_t cycles) { budget_ = cycles; }

  // one instruction cycle, executed at pc with `depth` return addresses on
  // the hardware stack, ending at cycle now. Returns the word's flags, with
  // kOverrun when this cycle took the step over its budget (the caller stops
  // on kOutside and kOverrun).
  uint8_t cycle(uint32_t pc, uint64_t now, int depth) {
    const uint32_t w = pc >> 1;
    const uint8_t f = w < flags_.size() ? flags_[w] : static_cast<uint8_t>(kOutside);
    ++s_.cycles;
    if ((f & kWaitEntry) && pc != last_pc_) {
      wait_entered(now);
      wait_depth_ = depth;
    }
    last_pc_ = pc;
    if (f & kIdle) {
      idle_ = true;  // the wait has flushed and idles: so does all it does until it returns
    } else {
      ++s_.busy_total;
      if (idle_ && depth < wait_depth_) idle_ = false;  // the wait returned: the main line works
    }
    if (!idle_) ++busy_;
    if (budget_ && started_ && busy_ > budget_ && !over_) {
      over_ = true;
      ++s_.overruns;
      return f | kOverrun;
    }
    return f;
  }

  uint64_t step_busy() const { return busy_; }
  uint64_t step_began() const { return step_start_; }
  bool started() const { return started_; }
  const CpuStats& stats() const { return s_; }

 private:
  void wait_entered(uint64_t now);

  std::vector<uint8_t> flags_;
  bool metering_ = true;
  uint64_t budget_ = 0;
  uint32_t last_pc_ = UINT32_MAX;
  bool started_ = false;
  uint64_t step_start_ = 0;
  uint64_t busy_ = 0;
  bool idle_ = false;    // the main line idles in a wait
  int wait_depth_ = 0;   // return addresses on the stack in the wait's own code
  bool over_ = false;
  CpuStats s_;
};

template <class Programmed>
std::vector<uint8_t> CpuMeter::flags_for(const PicBuild& b, uint32_t flash_bytes, Programmed programmed) {
  std::vector<uint8_t> f(flash_bytes / 2, 0);
  for (uint32_t w = 0; w < f.size(); ++w)
    if (!programmed(w * 2)) f[w] |= kOutside;
  const int64_t idle = b.code_at("_next_tick");
  if (idle >= 0) {
    const auto sz = b.section_size.find(static_cast<uint32_t>(idle));
    const uint32_t len = sz == b.section_size.end() ? 0 : sz->second;
    for (uint32_t a = static_cast<uint32_t>(idle); a < idle + len && a / 2 < f.size(); a += 2) f[a / 2] |= kIdle;
  }
  for (const char* wait : {"_hal_tick_wait", "_hal_delay_ms", "_hal_wait_event_ms"}) {
    const int64_t at = b.code_at(wait);
    if (at >= 0 && at / 2 < static_cast<int64_t>(f.size())) f[static_cast<size_t>(at / 2)] |= kWaitEntry;
  }
  return f;
}

}  // namespace chainsim::pic
