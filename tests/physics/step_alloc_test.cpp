// World::step() allocates nothing once the first step has set up ODE's
// stepping context. Counted by interposing glibc's malloc family in this test
// binary (libode's allocations go through them too).
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

TEST(World, StepDoesNotAllocate) {
#ifndef CHAINSIM_COUNT_MALLOC
  GTEST_SKIP() << "needs glibc malloc interposition";
#else
  const double deg = 3.14159265358979323846 / 180.0;
  WorldConfig c;
  c.chain.assign(8, "rotation");
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w(c);
  for (int m = 0; m < 8; ++m) w.set_servo_setpoint(m, 1, (m == 0 ? 25 : (m % 2 ? -50 : 50)) * deg);
  w.step();  // ODE sets up its stepping context here
  long total = 0;
  for (int k = 1; k < 10000; ++k) {  // 5 s of crawling: contacts come and go
    if (k % 20 == 0) {
      const double t = w.time_us() * 1e-6;
      for (int m = 0; m < 8; ++m) w.set_servo_setpoint(m, 0, 20 * deg * std::sin(14 * t + m * 1.36));
    }
    g_allocations = 0;
    g_counting = true;
    w.step();
    g_counting = false;
    total += g_allocations;
  }
  EXPECT_EQ(total, 0);
  // sanity: the counter does count
  g_allocations = 0;
  g_counting = true;
  void* volatile p = std::malloc(16);
  g_counting = false;
  std::free(p);
  EXPECT_EQ(g_allocations, 1);
#endif
}

}  // namespace
}  // namespace chainsim
