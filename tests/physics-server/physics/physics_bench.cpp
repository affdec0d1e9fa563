// Cost of the physics: microseconds of wall time per 0.5 ms step for chains of
// 2, 8 and 32 rotation modules crawling on the plane (the gait of
// gait_test.cpp), after a 1 s settling run. Prints figures, asserts nothing.
//   physics_bench [seconds=5] [iterations=<WorldConfig default>] [modules... = 2 8 32]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <vector>

#include "bench_args.h"
#include "model/units.h"
#include "physics/world.h"
#include "world_of.h"
#include "determinism/libm_variants.h"

using namespace chainsim;

int main(int argc, char** argv) {
  chainsim::use_baseline_libm("physics_bench", argv);  // the libm chainsim uses
  const char* usage = "physics_bench [seconds=5] [iterations=<WorldConfig default>] [modules... = 2 8 32]";
  bench::help_or_continue(argc, argv, usage);
  const double seconds = argc > 1 ? bench::positive(argv[1], "seconds", usage) : 5.0;
  const int iterations =
      argc > 2 ? bench::positive_int(argv[2], "iterations", usage) : WorldConfig{}.solver_iterations;
  const double deg = kRadPerDeg;
  std::vector<int> counts;
  for (int a = 3; a < argc; ++a) counts.push_back(bench::positive_int(argv[a], "modules", usage));
  if (counts.empty()) counts = {2, 8, 32};
  std::printf("QuickStep iterations %d, %.1f s simulated per chain\n", iterations, seconds);
  std::printf("%8s %7s %10s %12s %10s %12s %10s\n", "modules", "bodies", "us/step", "x real time",
              "contacts", "dock max mm", "moved m");
  for (int n : counts) {
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.0126);
    c.solver_iterations = iterations;
    World w = world_of(c, std::vector<std::string>(n, "rotation"));
    for (int m = 0; m < n; ++m)
      w.set_servo_setpoint(m, 1, (m == 0 ? 25 : (m % 2 ? -50 : 50)) * deg);
    auto drive = [&](int k) {
      if (k % 20 == 0) {
        const double t = w.time_us() * 1e-6;
        for (int m = 0; m < n; ++m)
          w.set_servo_setpoint(m, 0, 20 * deg * std::sin(14 * t + m * 1.36));
      }
    };
    int k = 0;
    for (; k < 2000; ++k) {
      drive(k);
      w.step();
    }
    const int steps = static_cast<int>(seconds / 5e-4);
    long contacts = 0;
    double dock = 0;
    const Eigen::Vector3d start = w.chain_com();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < steps; ++i, ++k) {
      drive(k);
      w.step();
      contacts += w.last_contact_count();
      if (i % 100 == 0) dock = std::max(dock, w.max_docking_error_m());
    }
    const double us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
        steps;
    std::printf("%8d %7d %10.1f %12.1f %10.1f %12.3f %10.3f\n", n, 3 * n, us, 500.0 / us,
                static_cast<double>(contacts) / steps, dock * 1e3, (w.chain_com() - start).x());
  }
  return 0;
}
