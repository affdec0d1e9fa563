// World::step() and World::sample() allocate nothing once the first step has
// set up ODE's stepping context, in pipes, on terrain and with every shipped
// type's sensors. Counted by interposing glibc's malloc family in this test
// binary (libode's allocations go through them too).
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdlib>

#include "physics/placement.h"
#include "physics/world.h"

#include "alloc_counter.h"
#include "world_of.h"

namespace chainsim {
namespace {

TEST(World, StepDoesNotAllocate) {
#ifndef CHAINSIM_COUNT_MALLOC
  GTEST_SKIP() << "needs glibc malloc interposition";
#else
  const double deg = kRadPerDeg;
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w = world_of(c, std::vector<std::string>(8, "rotation"));
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

// the same in the other environments: a chain of three rotation modules
// crawling down a pipe with an elbow (analytic and mesh colliders) and on
// the terrain (the trimesh colliders' caches are sized when the environment
// is built: EnvironmentGeoms::warm_up)
TEST(World, StepDoesNotAllocateInPipesAndOnTerrain) {
#ifndef CHAINSIM_COUNT_MALLOC
  GTEST_SKIP() << "needs glibc malloc interposition";
#else
  const double deg = kRadPerDeg;
  for (int env = 0; env < 3; ++env) {
    WorldConfig c;
    c.environment.ground_plane = false;
    if (env < 2) {
      c.environment.type = EnvironmentType::Pipe;
      PipeSegment a, b, d;
      a.length_m = 0.2;
      a.slope_deg = -20;
      b.type = PipeSegment::Type::Elbow;
      b.bend_radius_m = 0.06;
      b.direction_deg = 90;
      d.length_m = 0.3;
      c.environment.pipe.segments = {a, b, d};
      c.environment.pipe.inner_diameter_m = 0.04;
      c.environment.pipe.collider = env == 0 ? PipeCollider::Analytic : PipeCollider::Mesh;
      place_types_at_pipe_entry(&c, std::vector<std::string>(3, "rotation"), 0.04);
    } else {
      c.environment.type = EnvironmentType::Terrain;
      c.head_position = Eigen::Vector3d(0.1, 0, 0.054);  // clear of the crests (0.04 m)
    }
    World w = world_of(c, std::vector<std::string>(3, "rotation"));
    long total = 0;
    for (int k = 0; k < 6000; ++k) {  // 3 s
      if (k % 20 == 0) {
        const double t = w.time_us() * 1e-6;
        for (int m = 0; m < 3; ++m) w.set_servo_setpoint(m, 0, 30 * deg * std::sin(14 * t + m * 1.36));
      }
      g_allocations = 0;
      g_counting = k >= 1;  // the first step sets up ODE's stepping context
      w.step();
      g_counting = false;
      total += g_allocations;
    }
    EXPECT_EQ(total, 0) << (env == 0 ? "analytic pipe" : env == 1 ? "mesh pipe" : "terrain");
  }
#endif
}

// the exact solver (dWorldStep), whose working memory grows with the square
// of the rows: an inchworm gripping and pushing in a vertical pipe, the
// pads' contacts coming and going
TEST(World, ExactStepDoesNotAllocate) {
#ifndef CHAINSIM_COUNT_MALLOC
  GTEST_SKIP() << "needs glibc malloc interposition";
#else
  WorldConfig c;
  c.solver = WorldConfig::Solver::Exact;
  c.environment.type = EnvironmentType::Pipe;
  c.environment.pipe.inner_diameter_m = 0.04;
  PipeSegment up;
  up.length_m = 0.4;
  up.slope_deg = 90;
  c.environment.pipe.segments = {up};
  const std::vector<std::string> chain = {"support", "extension", "support"};
  place_types_at_pipe_entry(&c, chain, 0.05);
  World w = world_of(c, chain);
  long total = 0;
  for (int k = 0; k < 6000; ++k) {  // 3 s: the two supports grip in turn, the extension works
    const int phase = (k / 500) % 2;
    w.set_servo_setpoint(0, 0, phase == 0 ? 0.0 : kPi / 2);
    w.set_servo_setpoint(2, 0, phase == 0 ? kPi / 2 : 0.0);
    w.set_servo_setpoint(1, 0, phase == 0 ? 0.015 : 0.0);
    g_allocations = 0;
    g_counting = k >= 1;  // the first step sets up ODE's stepping context
    w.step();
    g_counting = false;
    total += g_allocations;
  }
  EXPECT_EQ(total, 0);
  EXPECT_GT(w.body_state(0, 0).position.z(), 0.05);  // it held on (the chain starts 5 cm in)
#endif
}

// with every shipped type's sensors (accelerometers, wheel encoders, touch,
// joint friction) sampled after each step
TEST(ShippedModules, StepAndSampleDoNotAllocate) {
#ifndef CHAINSIM_COUNT_MALLOC
  GTEST_SKIP() << "needs glibc malloc interposition";
#else
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w = world_of(c, {"touch", "rotation", "support", "extension", "helicoidal", "traveller", "traveller",
              "passive", "rotation"});
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
