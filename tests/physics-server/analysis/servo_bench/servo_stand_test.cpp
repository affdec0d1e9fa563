// The servo test stand as a library: the two solvers agree, the stand starts
// at rest at the first set-point and samples at the given times, bench files
// and set-point files read and fail as documented, the output format.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/servo_bench/bench_config.h"
#include "analysis/servo_bench/bench_csv.h"
#include "analysis/servo_bench/servo_stand.h"
#include "readers/csv_table.h"

namespace chainsim {
namespace {

// 1 kHz samples of a few moves with reversals
void moves(std::vector<double>* t, std::vector<double>* sp) {
  for (int k = 0; k <= 600; ++k) {
    t->push_back(k * 1e-3);
    sp->push_back(k < 20 ? 30 : k < 250 ? 120 : k < 400 ? 60 : 75);
  }
}

std::string bench_error(const std::string& yaml) {
  try {
    load_bench_text(yaml, "b.yaml");
  } catch (const BenchError& e) {
    return e.what();
  }
  return "(no error)";
}

// measured: 0.0021 deg and 12 uA apart at most on these moves, with or
// without backlash
TEST(ServoStand, ClosedFormAgreesWithOde) {
  std::vector<double> t, sp;
  moves(&t, &sp);
  BenchConfig b;
  b.load_torque_nm = 0.004;
  for (double backlash : {0.0, 2.0}) {  // and with an effect that has a discontinuity
    b.servo.backlash_deg = backlash;
    const auto ode = simulate_bench(b, t, sp, BenchSolver::ode_exact);
    const auto fast = simulate_bench(b, t, sp, BenchSolver::closed_form);
    ASSERT_EQ(ode.size(), t.size());
    double da = 0, dc = 0;
    for (size_t k = 0; k < t.size(); ++k) {
      da = std::max(da, std::fabs(ode[k].angle_deg - fast[k].angle_deg));
      dc = std::max(dc, std::fabs(ode[k].current_a - fast[k].current_a));
    }
    std::printf("backlash %.0f deg: closed form vs ODE: max angle diff %.3g deg, current %.3g A; at 240 ms %.3f deg\n",
                backlash, da, dc, fast[240].angle_deg);
    EXPECT_LT(da, 0.01);
    EXPECT_LT(dc, 1e-4);
    // they move: 30 -> 120, short of it by the load torque's R / (Kt Kp) = 1.6 degrees
    EXPECT_NEAR(fast[240].angle_deg, 120 + 0.004 * 12 / (0.14 * 12) * 180 / 3.14159265358979, 0.1);
  }
}

TEST(ServoStand, StartsAtRestAtTheFirstSetPointAndSamplesAtTheGivenTimes) {
  const std::vector<double> t = {5.0, 5.01, 5.0203, 5.5};
  const std::vector<double> sp = {-40, 10, 10, 10};
  const auto s = simulate_bench(BenchConfig{}, t, sp, BenchSolver::closed_form);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].angle_deg, -40.0);
  EXPECT_EQ(s[1].angle_deg, -40.0);
  EXPECT_EQ(s[1].current_a, 0.0);   // a set-point acts from the step after its time
  EXPECT_GT(s[2].angle_deg, -40.0);  // the move has begun
  EXPECT_NEAR(s[3].angle_deg, 10.0, 0.1);
  EXPECT_THROW(simulate_bench(BenchConfig{}, {}, {}), std::invalid_argument);
  EXPECT_THROW(simulate_bench(BenchConfig{}, {0, 1}, {0}), std::invalid_argument);
}

// the calibration's training fits run only as far as their last sample: a
// run cut at a count gives the whole run's first samples, bit for bit
TEST(ServoStand, ARunCutShortGivesTheWholeRunsFirstSamples) {
  std::vector<double> t, sp;
  moves(&t, &sp);
  BenchConfig b;
  b.servo.coulomb_nm = 0.004;
  b.servo.backlash_deg = 1.5;
  for (BenchSolver solver : {BenchSolver::closed_form, BenchSolver::ode_exact}) {
    const auto whole = simulate_bench(b, t, sp, solver);
    for (size_t count : {size_t{1}, size_t{251}, t.size() - 1}) {
      const auto part = simulate_bench(b, t, sp, solver, count);
      ASSERT_EQ(part.size(), count);
      for (size_t k = 0; k < count; ++k) {
        ASSERT_EQ(part[k].angle_deg, whole[k].angle_deg) << k;
        ASSERT_EQ(part[k].current_a, whole[k].current_a) << k;
      }
    }
    EXPECT_EQ(simulate_bench(b, t, sp, solver, t.size() + 5).size(), t.size());
  }
}

// benches stepped side by side give each the bytes it gives alone, whatever
// its effects and however many samples each asks for
TEST(ServoStand, BenchesSideBySideGiveEachItsOwnRun) {
  std::vector<double> t, sp;
  moves(&t, &sp);
  std::vector<BenchConfig> b(4);
  b[0].servo.pwm_frame_s = 0.0167, b[0].servo.pwm_frame_phase_s = 0.004, b[0].servo.current_limit_a = 0.2;
  b[1].servo.backlash_deg = 2, b[1].servo.backlash_stiffness_nm_rad = 30;
  b[2].servo.coulomb_nm = 0.004, b[2].load_torque_nm = 0.003;
  b[3].servo.supply_sag_ohm = 6, b[3].servo.supply_rail_f = 1e-3, b[3].servo.i_threshold_a = 0.02;
  for (BenchConfig& c : b) c.dt_us = 100;
  const std::vector<std::vector<size_t>> counts = {
      {t.size(), t.size()}, {t.size(), 251}, {1, t.size()}, {t.size(), 300, t.size() + 9, 2}};
  for (BenchSolver solver : {BenchSolver::closed_form, BenchSolver::ode_exact}) {
    for (const std::vector<size_t>& n : counts) {
      for (size_t first = 0; first + n.size() <= b.size(); first += 2) {
        std::vector<const BenchConfig*> benches;
        for (size_t i = 0; i < n.size(); ++i) benches.push_back(&b[first + i]);
        const auto runs = simulate_benches(benches, t, sp, solver, n);
        ASSERT_EQ(runs.size(), n.size());
        for (size_t i = 0; i < n.size(); ++i) {
          const auto alone = simulate_bench(*benches[i], t, sp, solver, n[i]);
          ASSERT_EQ(runs[i].size(), std::min(n[i], t.size()));
          ASSERT_EQ(runs[i].size(), alone.size());
          for (size_t k = 0; k < alone.size(); ++k) {
            ASSERT_EQ(runs[i][k].angle_deg, alone[k].angle_deg) << "bench " << first + i << " sample " << k;
            ASSERT_EQ(runs[i][k].current_a, alone[k].current_a) << "bench " << first + i << " sample " << k;
          }
        }
      }
    }
  }
  // the benches differ from each other (the test would pass on one bench copied)
  for (size_t i = 1; i < b.size(); ++i) {
    const auto a = simulate_bench(b[i - 1], t, sp, BenchSolver::closed_form);
    const auto c = simulate_bench(b[i], t, sp, BenchSolver::closed_form);
    double most = 0;
    for (size_t k = 0; k < t.size(); ++k) most = std::max(most, std::fabs(a[k].angle_deg - c[k].angle_deg));
    EXPECT_GT(most, 0.1) << "benches " << i - 1 << " and " << i;
  }
  // one step for all, a count per bench
  BenchConfig other = b[0];
  other.dt_us = 200;
  EXPECT_THROW(simulate_benches({&b[0], &other}, t, sp, BenchSolver::closed_form, {5, 5}), std::invalid_argument);
  EXPECT_THROW(simulate_benches({&b[0], &b[1]}, t, sp, BenchSolver::closed_form, {5}), std::invalid_argument);
  EXPECT_THROW(simulate_benches({}, t, sp, BenchSolver::closed_form, {}), std::invalid_argument);
}

TEST(ServoStand, BenchFilesSetWhatTheyNameAndNameWhatIsWrong) {
  const BenchConfig b =
      load_bench_text("servo: {Kp: 10, coulomb_nm: 0.01}\nload: {inertia_kgm2: 2e-5}\nsim: {dt_us: 100}\n", "b.yaml");
  EXPECT_EQ(b.servo.kp, 10);
  EXPECT_EQ(b.servo.coulomb_nm, 0.01);
  EXPECT_EQ(b.servo.km, ServoParams{}.km);  // untouched
  EXPECT_EQ(b.load_inertia_kgm2, 2e-5);
  EXPECT_EQ(b.dt_us, 100);
  EXPECT_EQ(load_bench_text("", "b.yaml").dt_us, 500);  // empty: the defaults
  EXPECT_EQ(bench_error("servo:\n  Kq: 1\n"),
            "b.yaml:2:3: unknown key 'Kq' in 'servo' (known: B, J, Km, Kp, Kt, L, R, backlash_deg, "
            "backlash_stiffness_nm_rad, coulomb_nm, current_limit_a, deadband_comparator_deg, deadband_deg, "
            "i_threshold_a, pwm_frame_phase_s, pwm_frame_s, pwm_pulse_s_per_deg, supply_rail_f, "
            "supply_sag_linear_ohm, supply_sag_ohm, supply_v)");
  EXPECT_EQ(bench_error("servo: {R: 0}\n"), "b.yaml:1:12: 'servo.R' = 0 must be > 0");
  EXPECT_EQ(bench_error("sim: {dt_us: 12.5}\n"), "b.yaml:1:14: 'sim.dt_us' must be an integer, not '12.5'");
  EXPECT_NE(bench_error("servo: {J: 0}\nload: {inertia_kgm2: 0}\n").find("b.yaml:2:7: "), std::string::npos);
  EXPECT_EQ(bench_error("servo: {pwm_pulse_s_per_deg: 1e-5}\n"),
            "b.yaml:1:8: 'servo': 'pwm_pulse_s_per_deg' needs 'pwm_frame_s' (the pulses come once a frame)");
  EXPECT_NE(bench_error("servo: {deadband_deg: 1, deadband_comparator_deg: 1}\n").find("two forms of one deadband"),
            std::string::npos);
  EXPECT_THROW(load_bench_config("/no/such/bench.yaml"), BenchError);
}

TEST(ServoStand, SetPointsAreATimeSeriesAndTheOutputHasNoNegativeZero) {
  const std::string path = testing::TempDir() + "/servo_stand_test_" + std::to_string(getpid()) + ".csv";
  std::ofstream(path) << "setpoint_deg,t_s\n30,0\n120,0.002\n";
  const SetpointProgram p = read_setpoints(path);
  ASSERT_EQ(p.t_s.size(), 2u);
  EXPECT_EQ(p.setpoint_deg[1], 120);
  EXPECT_EQ(format_bench_csv(p, {{30, 0}, {-1e-7, -2e-8}}),
            "t_s,setpoint_deg,angle_deg,current_a\n0.000000,30.0000,30.0000,0.000000\n"
            "0.002000,120.0000,0.0000,0.000000\n");
  std::ofstream(path) << "t_s,setpoint_deg\n0,30\n0,40\n";
  try {
    read_setpoints(path);
    FAIL() << "no error";
  } catch (const CsvError& e) {
    EXPECT_NE(std::string(e.what()).find(":3:1: t_s = 0 is not after the previous row's 0 (line 2)"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(path) << "t_s,setpoint_deg\n0,30\n20000,40\n";
  EXPECT_THROW(read_setpoints(path), CsvError);  // more than kMaxBenchSpan_s
  std::remove(path.c_str());
}

}  // namespace
}  // namespace chainsim
