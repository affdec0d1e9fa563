// The chip's busy time per step, from its program counter and stack depth
// (tools/pic-module/cpu_meter.h), on a made-up program memory: code at
// 0x100, a wait at 0x200 (polling at 0x210), the idle loop at 0x300, an
// interrupt routine at 0x018.
#include <gtest/gtest.h>

#include "pic-module/cpu_meter.h"

using chainsim::pic::CpuMeter;

namespace {

constexpr uint32_t kCode = 0x100, kWait = 0x200, kPoll = 0x210, kIdle = 0x300, kIsr = 0x018;

CpuMeter meter() {
  std::vector<uint8_t> f(0x400 / 2, 0);
  f[kWait / 2] |= CpuMeter::kWaitEntry;
  f[kIdle / 2] |= CpuMeter::kIdle;
  f[(kIdle + 2) / 2] |= CpuMeter::kIdle;
  for (uint32_t w = 0x380 / 2; w < f.size(); ++w) f[w] |= CpuMeter::kOutside;
  return CpuMeter(f);
}

// n cycles at pc and depth
void run(CpuMeter& m, uint64_t& now, uint32_t pc, int depth, int n) {
  for (int i = 0; i < n; ++i) m.cycle(pc, ++now, depth);
}

// a step: work at depth 1, the wait's entry and its flush, then idle with
// interrupts cutting in
void step(CpuMeter& m, uint64_t& now, int work, int flush, int idle, int isr) {
  run(m, now, kCode, 1, work);
  run(m, now, kWait, 2, 1);        // the wait's first instruction
  run(m, now, kPoll, 2, flush);    // its flush of the outputs
  run(m, now, kIdle, 3, idle / 2);
  run(m, now, kIsr, 4, isr);       // an interrupt on top of the idle loop
  run(m, now, kPoll, 2, 3);        // the wait's polling between ticks
  run(m, now, kIdle, 3, idle - idle / 2);
}

}  // namespace

TEST(CpuMeter, AStepIsTheMainLinesWorkFromAWaitsReturnToTheNextWaitsIdleLoop) {
  CpuMeter m = meter();
  uint64_t now = 0;
  run(m, now, kCode, 1, 500);  // start-up
  for (int i = 0; i < 10; ++i) step(m, now, 1000, 200, 3000, 100);
  run(m, now, kCode, 1, 10);
  run(m, now, kWait, 2, 1);  // ends the tenth step
  const auto& s = m.stats();
  // the start-up runs to the first wait: the first step's work is part of it
  EXPECT_EQ(s.startup_cycles, 500u + 1000);
  EXPECT_EQ(s.steps, 10u);
  // each step: the wait's first instruction and its flush (201), then from
  // the idle loop on nothing (the interrupt and the polling idle), then the
  // next step's work (the last: 10 cycles)
  EXPECT_EQ(s.busy_worst, 1u + 200 + 1000);
  EXPECT_EQ(s.busy_sum, 9u * (1 + 200 + 1000) + (1 + 200 + 10));
  EXPECT_EQ(s.period_sum, 9u * (1 + 200 + 3000 + 100 + 3 + 1000) + (1 + 200 + 3000 + 100 + 3 + 10));
  // the load counts the interrupt and the polling too
  EXPECT_EQ(s.busy_total, 500u + 10 * (1000 + 1 + 200 + 100 + 3) + 10 + 1);
}

TEST(CpuMeter, AnInterruptDuringTheWorkDelaysTheStepAndCounts) {
  CpuMeter m = meter();
  uint64_t now = 0;
  run(m, now, kWait, 2, 1);
  run(m, now, kIdle, 3, 10);
  run(m, now, kCode, 1, 300);
  run(m, now, kIsr, 2, 50);  // cuts into the work
  run(m, now, kCode, 1, 300);
  run(m, now, kWait, 2, 1);
  EXPECT_EQ(m.stats().busy_worst, 650u + 1);
}

TEST(CpuMeter, AStepOverTheBudgetIsAnOverrunAtTheCycleItGoesOverOnce) {
  CpuMeter m = meter();
  m.set_budget(900);
  uint64_t now = 0;
  run(m, now, kWait, 2, 1);
  step(m, now, 800, 50, 1000, 10);
  EXPECT_EQ(m.stats().overruns, 0u);
  // the next step: the wait's entry and flush (51), then work
  int over_at = -1;
  for (int i = 0; i < 2000; ++i)
    if ((m.cycle(kCode, ++now, 1) & CpuMeter::kOverrun) && over_at < 0) over_at = i;
  EXPECT_EQ(over_at, 900 - 51) << "the cycle that took the step over 900";
  run(m, now, kWait, 2, 1);
  step(m, now, 100, 50, 1000, 10);
  EXPECT_EQ(m.stats().overruns, 1u) << "reported once a step";
}

TEST(CpuMeter, CodeOutsideTheProgramIsFlagged) {
  CpuMeter m = meter();
  uint64_t now = 0;
  EXPECT_FALSE(m.cycle(kCode, ++now, 1) & CpuMeter::kOutside);
  EXPECT_TRUE(m.cycle(0x390, ++now, 1) & CpuMeter::kOutside);
  EXPECT_TRUE(m.cycle(0x8000, ++now, 1) & CpuMeter::kOutside) << "beyond the program memory";
}
