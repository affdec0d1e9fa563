// Cost of the calibration's model runs: CPU time of one closed-form run of
// the servo test stand (simulate_benches, what every candidate fit of
// `chainsim calibrate` runs thousands of times) on a 4 s record at the
// calibration's 100 us step, for the base model and each catalogue effect,
// one stand alone and two side by side; and the latency of the Coulomb
// friction's tanh, the library's and fast_tanh, side by side. Prints
// figures, asserts nothing. Figures of record: docs/benchmarks.md ("Servo
// calibration's model runs").
//   servo_stand_bench [repeats=15]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "analysis/servo_bench/servo_stand.h"
#include "bench_args.h"
#include "bench_clock.h"
#include "determinism/libm_variants.h"
#include "physics/actuators/fast_tanh.h"

using namespace chainsim;

namespace {

double cpu_ms() { return bench::cpu_us() * 1e-3; }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// ns per call of f, each call waiting for the last: the arguments are the
// friction's below its saturation (w / ws near rest, where the step's
// tanh is not +-1: a product of three uniforms, mostly near 0), each made
// to depend on the last result by a perturbation below its last bit
template <class F>
double chained_ns(F f, const std::vector<double>& args, int calls) {
  double y = 0.0, sum = 0.0;
  const double t0 = cpu_ms();
  for (int i = 0; i < calls; ++i) {
    y = f(args[i % args.size()] + y * 1e-300);
    sum += y;
  }
  const double t1 = cpu_ms();
  if (sum == 12345.678) std::printf(" ");   // keeps the loop
  return (t1 - t0) * 1e6 / calls;
}

}  // namespace

int main(int argc, char** argv) {
  chainsim::use_baseline_libm("servo_stand_bench", argv);  // the libm chainsim uses
  const char* usage = "servo_stand_bench [repeats=15]";
  bench::help_or_continue(argc, argv, usage);
  const int repeats = argc > 1 ? bench::positive_int(argv[1], "repeats", usage) : 15;

  // a bench record's set-points: 4 s at 657 Hz, the set-point profile of
  // one of the calibration study's records (coulomb_friction+current_limit,
  // seed 107): large moves and small corrections, a change every 0.25-0.36 s
  std::vector<double> t, sp;
  const double change_s[] = {0, 0.108, 0.463, 0.72, 0.956, 1.315, 1.561, 1.807, 2.153, 2.417, 2.67, 3.003, 3.26,
                             3.611, 3.868};
  const double angle_deg[] = {30, 120, 100, 104, 60, 63, 58, 110, 90, 93, 140, 135, 80, 84, 70};
  for (int k = 0, c = 0; k < 2628; ++k) {
    t.push_back(k / 657.0);
    while (c + 1 < 15 && change_s[c + 1] <= t.back()) ++c;
    sp.push_back(angle_deg[c]);
  }
  BenchConfig base;
  base.dt_us = 100;
  base.load_inertia_kgm2 = 2e-5;
  base.load_torque_nm = 0.004;
  struct Effect {
    const char* name;
    std::function<void(ServoParams&)> set;
  };
  const std::vector<Effect> effects = {
      {"none", [](ServoParams&) {}},
      {"static_friction_threshold", [](ServoParams& p) { p.i_threshold_a = 0.05; }},
      {"coulomb_friction", [](ServoParams& p) { p.coulomb_nm = 0.0046; }},
      {"backlash", [](ServoParams& p) { p.backlash_deg = 1.0; }},
      {"deadband", [](ServoParams& p) { p.deadband_deg = 1.0; }},
      {"supply_sag", [](ServoParams& p) { p.supply_sag_ohm = 2.0; }},
      {"pwm_frame_delay", [](ServoParams& p) { p.pwm_frame_s = 0.02, p.pwm_frame_phase_s = 0.007; }},
      {"current_limit", [](ServoParams& p) { p.current_limit_a = 0.22; }},
      {"coulomb_friction+current_limit", [](ServoParams& p) { p.coulomb_nm = 0.0046, p.current_limit_a = 0.22; }},
  };
  const double steps = 4.0 / 100e-6;
  std::printf("closed-form stand, 4 s record at 657 Hz, 100 us step (%.0f steps a run), median of %d\n", steps,
              repeats);
  std::printf("%-32s %12s %12s %14s %14s\n", "effect", "ms/run alone", "ns/step", "ms/run paired", "paired/alone");
  for (const Effect& e : effects) {
    BenchConfig a = base, b = base;
    e.set(a.servo);
    e.set(b.servo);
    b.servo.kp *= 1.01;   // the pair: two parameter sets, as a fit's runs
    std::vector<double> alone, paired;
    for (int r = 0; r < repeats; ++r) {
      const double t0 = cpu_ms();
      simulate_benches({&a}, t, sp, BenchSolver::closed_form, {t.size()});
      const double t1 = cpu_ms();
      simulate_benches({&a, &b}, t, sp, BenchSolver::closed_form, {t.size(), t.size()});
      const double t2 = cpu_ms();
      alone.push_back(t1 - t0);
      paired.push_back((t2 - t1) / 2);
    }
    const double m1 = median(alone), m2 = median(paired);
    std::printf("%-32s %12.3f %12.1f %14.3f %14.2f\n", e.name, m1, m1 * 1e6 / steps, m2, m2 / m1);
  }
  const int calls = 5000000;
  std::vector<double> args(4096);
  std::mt19937_64 g(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& a : args) a = 27.0 * u(g) * u(g) * u(g);   // -27..27: 0.4 % beyond +-20
  std::vector<double> lib, fast;
  for (int r = 0; r < std::max(3, repeats / 3); ++r) {
    lib.push_back(chained_ns([](double x) { return std::tanh(x); }, args, calls));
    fast.push_back(chained_ns([](double x) { return fast_tanh(x); }, args, calls));
  }
  std::printf("tanh of the friction's arguments, each call waiting for the last: the library's %.1f ns, "
              "fast_tanh %.1f ns (%.2fx)\n",
              median(lib), median(fast), median(fast) / median(lib));
  return 0;
}
