// World::step() and World::sample() allocate nothing with the shipped types'
// sensors (accelerometers, wheel encoders, touch, joint friction). Counted by
// interposing glibc's malloc family in this test binary, as in
// tests/physics/step_alloc_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>

#include "world.h"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define CHAINSIM_COUNT_MALLOC 1
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
}
namespace {
thread_local bool g_counting = false;
thread_local long g_allocations = 0;
}  // namespace
extern "C" void* malloc(size_t n) {
  if (g_counting) ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void* calloc(size_t a, size_t b) {
  if (g_counting) ++g_allocations;
  return __libc_calloc(a, b);
}
extern "C" void* realloc(void* p, size_t n) {
  if (g_counting) ++g_allocations;
  return __libc_realloc(p, n);
}
#endif

namespace chainsim {
namespace {

TEST(ShippedModules, StepAndSampleDoNotAllocate) {
#ifndef CHAINSIM_COUNT_MALLOC
  GTEST_SKIP() << "needs glibc malloc interposition";
#else
  WorldConfig c;
  c.chain = {"touch",     "rotation",  "support", "extension", "helicoidal",
             "traveller", "traveller", "passive", "rotation"};
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w(c);
  w.step();  // ODE sets up its stepping context here
  long total = 0;
  ModuleSample s;
  for (int k = 1; k < 4000; ++k) {  // 2 s: servos moving, the screw pushing, contacts changing
    if (k % 20 == 0) {
      const double t = w.time_us() * 1e-6;
      w.set_servo_setpoint(1, 0, 0.3 * std::sin(14 * t));
      w.set_servo_setpoint(2, 0, 0.6 + 0.5 * std::sin(5 * t));
      w.set_servo_setpoint(3, 0, 0.007 + 0.007 * std::sin(5 * t));
      w.set_servo_setpoint(4, 0, std::sin(3 * t));
    }
    g_allocations = 0;
    g_counting = true;
    w.step();
    for (int m = 0; m < w.module_count(); ++m) w.sample(m, &s);
    g_counting = false;
    total += g_allocations;
  }
  EXPECT_EQ(total, 0);
#endif
}

}  // namespace
}  // namespace chainsim
