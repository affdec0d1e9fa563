// The servo calibration as a library, on records made with the bench model
// itself plus measurement noise: a hidden catalogue effect is found and the
// gap shrinks; without one, nothing is added; the report files say so.
// (tests/physics-server/analysis/calibration/calibration_test.cpp runs
// `chainsim calibrate` on records from an integrator of its own, synth.h.)
#include "analysis/calibration/servo_calibration.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "analysis/calibration/calibration_report.h"

namespace chainsim {
namespace {

// the datasheet the calibration is given: the bench defaults with a load torque
BenchConfig datasheet() {
  BenchConfig b;
  b.load_torque_nm = 0.004;
  return b;
}

// 4 s at 1 kHz of moves, reversals and holds, from the bench model with
// `truth`, plus 0.2 deg and 2 mA of noise
MeasuredRecord bench_record(BenchConfig truth, unsigned seed) {
  const std::vector<std::pair<double, double>> prog = {
      {0.0, 30},   {0.107, 120}, {0.462, 100}, {0.719, 104}, {0.955, 60},  {1.314, 63}, {1.561, 58}, {1.806, 110},
      {2.153, 90}, {2.417, 93},  {2.668, 140}, {3.002, 135}, {3.259, 80},  {3.611, 84}, {3.866, 70}};
  MeasuredRecord m;
  m.has_current = true;
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
    m.current.push_back(x.current_a + ni(rng));
  }
  return m;
}

std::vector<std::string> effect_names(const Fit& f) {
  std::vector<std::string> out;
  for (int e : f.effects) out.push_back(effect_catalogue()[e].name);
  return out;
}

TEST(ServoCalibration, FindsAHiddenDeadbandAndShrinksTheGap) {
  BenchConfig truth = datasheet();
  truth.servo.kp *= 1.05;   // the base a little off the datasheet
  truth.servo.r *= 0.96;
  truth.servo.deadband_deg = 3.0;
  const ServoCalibration c = calibrate_servo(datasheet(), bench_record(truth, 7), [](const std::string&) {});
  std::printf("deadband: verdict %s, gap %.4f -> %.4f, whiteness %.3f -> %.3f, %d model runs\n", c.verdict.c_str(),
              c.base.gap, c.search.model.gap, c.base.white, c.search.model.white, c.problem.model_runs);
  EXPECT_EQ(c.verdict, "explained");
  ASSERT_EQ(effect_names(c.final_fit), std::vector<std::string>{"deadband"});
  EXPECT_NEAR(c.final_fit.x[kNumBase], 3.0, 0.3);
  EXPECT_LT(c.search.model.gap, 0.5 * c.base.gap);
  EXPECT_NEAR(c.final_fit.x[0], 1.05, 0.03);   // Kp factor
  // the interval of the effect's width contains it
  EXPECT_LE(c.ci[kNumBase].first, 3.0);
  EXPECT_GE(c.ci[kNumBase].second, 3.0);
  // the round that accepted it says why, the others were less good
  ASSERT_FALSE(c.search.rounds.empty());
  EXPECT_TRUE(c.search.rounds[0][0].accepted);
  EXPECT_NE(c.search.rounds[0][0].why.find("accepted"), std::string::npos);
  EXPECT_LT(c.ode_check_max_angle_diff_deg, 0.01);
}

TEST(ServoCalibration, NoEffectIsAddedWhenNoneIsMissingAndTheReportSaysSo) {
  BenchConfig truth = datasheet();
  truth.servo.kp *= 0.97;
  const ServoCalibration c = calibrate_servo(datasheet(), bench_record(truth, 8), [](const std::string&) {});
  EXPECT_EQ(c.verdict, "no_missing_effect");
  EXPECT_TRUE(c.final_fit.effects.empty());
  EXPECT_LE(c.base.white, kWhiteMax);

  const std::string dir = testing::TempDir() + "/servo_calibration_test";
  std::filesystem::create_directories(dir);
  write_calibration_report(c, "", "m.csv", dir);
  std::ifstream jf(dir + "/report.json");
  const nlohmann::json j = nlohmann::json::parse(jf);
  EXPECT_EQ(j["verdict"], "no_missing_effect");
  EXPECT_TRUE(j["effects"].empty());
  EXPECT_NEAR(j["base"]["Kp"]["factor"].get<double>(), 0.97, 0.02);
  EXPECT_EQ(j["model_runs"].get<int>(), c.problem.model_runs);
  std::ifstream mf(dir + "/report.md");
  std::stringstream md;
  md << mf.rdbuf();
  EXPECT_NE(md.str().find("**Verdict: no_missing_effect**"), std::string::npos);
  EXPECT_NE(md.str().find("Bench file: `(defaults)`"), std::string::npos);
  for (const char* f : {"angle.svg", "residual.svg", "current.svg"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  std::filesystem::remove_all(dir);
  EXPECT_THROW(write_calibration_report(c, "", "m.csv", dir + "/no/such/dir"), ReportError);
}

}  // namespace
}  // namespace chainsim
