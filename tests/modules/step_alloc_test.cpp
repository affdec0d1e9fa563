// World::step() and World::sample() allocate nothing with the shipped types'
// sensors (accelerometers, wheel encoders, touch, joint friction). Counted by
// interposing glibc's malloc family in this test binary, as in
// tests/physics/step_alloc_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>

#include "world.h"

#include "alloc_counter.h"

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
