// Records made with the bench model itself plus measurement noise, for the
// calibration's library tests (the ctest and the study use the separate
// generators of synth.h and synth_b.h).
#pragma once

#include <random>
#include <utility>
#include <vector>

#include "analysis/calibration/measured_record.h"
#include "analysis/servo_bench/servo_stand.h"

namespace chainsim {

// the datasheet the calibration is given: the bench defaults with a load torque
inline BenchConfig test_datasheet() {
  BenchConfig b;
  b.load_torque_nm = 0.004;
  return b;
}

// 4 s at 1 kHz of moves, reversals and holds, from the bench model with
// `truth`, plus 0.2 deg and 2 mA of noise (no current column: with_current false)
inline MeasuredRecord bench_record(BenchConfig truth, unsigned seed, bool with_current = true) {
  const std::vector<std::pair<double, double>> prog = {
      {0.0, 30},   {0.107, 120}, {0.462, 100}, {0.719, 104}, {0.955, 60},  {1.314, 63}, {1.561, 58}, {1.806, 110},
      {2.153, 90}, {2.417, 93},  {2.668, 140}, {3.002, 135}, {3.259, 80},  {3.611, 84}, {3.866, 70}};
  MeasuredRecord m;
  m.has_current = with_current;
  size_t p = 0;
  for (int k = 0; k <= 4000; ++k) {
    const double t = k * 1e-3;
    while (p + 1 < prog.size() && prog[p + 1].first <= t + 1e-12) ++p;
    m.t.push_back(t);
    m.sp.push_back(prog[p].second);
  }
  truth.dt_us = 100;
  const std::vector<BenchSample> s = simulate_bench(truth, m.t, m.sp, BenchSolver::closed_form);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> na(0, 0.2), ni(0, 0.002);
  for (const BenchSample& x : s) {
    m.angle.push_back(x.angle_deg + na(rng));
    const double i = x.current_a + ni(rng);
    if (with_current) m.current.push_back(i);
  }
  return m;
}

}  // namespace chainsim
