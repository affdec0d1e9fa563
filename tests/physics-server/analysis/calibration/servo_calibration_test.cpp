// The servo calibration as a library, on records made with the bench model
// itself plus measurement noise: a hidden catalogue effect is found and the
// gap shrinks; without one, nothing is added; the report files say so.
// (tests/physics-server/analysis/calibration/calibration_test.cpp runs
// `chainsim calibrate` on records from an integrator of its own, synth.h.)
#include "analysis/calibration/servo_calibration.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "analysis/calibration/calibration_report.h"
#include "analysis/calibration/paired_runs.h"
#include "analysis/servo_bench/bench_config.h"
#include "analysis/servo_bench/bench_csv.h"
#include "bench_record.h"

namespace chainsim {
namespace {

BenchConfig datasheet() { return test_datasheet(); }

std::vector<std::string> effect_names(const Fit& f) {
  std::vector<std::string> out;
  for (int e : f.effects) out.push_back(effect_catalogue()[e].name);
  return out;
}

// the datasheet starts of every round: run where the effect's first start
// gained at least a quarter of its round's best first start, and only there;
// the report's words say which were not run. The number not run
int check_datasheet_starts(const ServoCalibration& c) {
  int skipped = 0;
  for (const SearchRound& r : c.search.rounds)
    for (const Candidate& cd : r.candidates) {
      if (cd.screen.stopped || both_starts_at_once(cd.effect) || !cd.fit.valid) continue;
      skipped += cd.second_start_skipped;
      EXPECT_EQ(cd.second_start_skipped, !run_second_start(cd.first_gain, cd.round_first_gain)) << cd.why;
      EXPECT_EQ(cd.second_start_skipped, cd.why.find("first start only") != std::string::npos) << cd.why;
      if (cd.accepted) {
        EXPECT_FALSE(cd.second_start_skipped);
      }
    }
  return skipped;
}

TEST(ServoCalibration, FindsAHiddenDeadbandAndShrinksTheGap) {
  BenchConfig truth = datasheet();
  truth.servo.kp *= 1.05;   // the base a little off the datasheet
  truth.servo.r *= 0.96;
  truth.servo.deadband_deg = 3.0;
  const ServoCalibration c = calibrate_servo(datasheet(), bench_record(truth, 7), [](const std::string&) {});
  std::printf("deadband: verdict %s, gap %.4f -> %.4f, whiteness %.3f -> %.3f, %d model runs\n", c.verdict.c_str(),
              c.gap_before, c.gap_after, c.base.white, c.search.model.white, c.model_runs);
  EXPECT_EQ(c.verdict, "explained");
  ASSERT_EQ(effect_names(c.final_fit), std::vector<std::string>{"deadband"});
  EXPECT_NEAR(c.final_fit.x[kNumBase], 3.0, 0.3);
  EXPECT_LT(c.gap_after, 0.5 * c.gap_before);
  EXPECT_NEAR(c.final_fit.x[0], 1.05, 0.03);   // Kp factor
  // the interval of the effect's width contains it
  EXPECT_LE(c.ci[kNumBase].first, 3.0);
  EXPECT_GE(c.ci[kNumBase].second, 3.0);
  // the round that accepted it says why, the others were less good
  ASSERT_FALSE(c.search.rounds.empty());
  EXPECT_TRUE(c.search.rounds[0].candidates[0].accepted);
  EXPECT_NE(c.search.rounds[0].candidates[0].why.find("accepted"), std::string::npos);
  EXPECT_FALSE(c.search.rounds[0].candidates[0].screen.stopped);
  check_datasheet_starts(c);
  // the last round only confirms: candidates that show no gain stop at the
  // screen, after exactly its model runs, and are not accepted
  int stopped = 0;
  for (const Candidate& cd : c.search.rounds.back().candidates) {
    if (!cd.screen.stopped) continue;
    ++stopped;
    EXPECT_EQ(cd.fit.evals, cd.screen.after);
    EXPECT_GT(cd.fit.train, cd.screen.loss);
    EXPECT_FALSE(cd.accepted);
    EXPECT_NE(cd.why.find("not fitted in full"), std::string::npos) << cd.why;
  }
  std::printf("last round: %d of %zu candidates stopped at the screen\n", stopped,
              c.search.rounds.back().candidates.size());
  EXPECT_GE(stopped, 3);
  EXPECT_LT(c.ode_check_max_angle_diff_deg, 0.01);
}

// two hidden effects, one far larger: in round 1 the supply sag's forms,
// which trim some of the misfit, are far behind the Coulomb friction and are
// fitted from their first start only; both effects are still found
TEST(ServoCalibration, ACandidateFarBehindItsRoundIsNotFittedFromTheDatasheetStart) {
  BenchConfig truth = datasheet();
  truth.servo.kp *= 1.04;
  truth.servo.r *= 0.97;
  truth.servo.coulomb_nm = 0.0075;
  truth.servo.current_limit_a = 0.27;
  const ServoCalibration c = calibrate_servo(datasheet(), bench_record(truth, 3), [](const std::string&) {});
  const int skipped = check_datasheet_starts(c);
  std::printf("coulomb + current limit: verdict %s, %d datasheet starts not run, %d model runs\n", c.verdict.c_str(),
              skipped, c.model_runs);
  std::vector<std::string> names = effect_names(c.final_fit);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"coulomb_friction", "current_limit"}));
  EXPECT_GE(skipped, 1);
}

// the candidates and starts fitted two at a time (paired_runs.h) give the
// report and the progress lines, byte for byte, of one after the other: a
// record with a frame clock (both starts at once, several clocks) and a
// supply sag through a rail capacitor (two forms, each with a refining form)
TEST(ServoCalibration, FittingTwoAtATimeChangesNothingButTheTime) {
  BenchConfig truth = datasheet();
  truth.servo.kp *= 1.03;
  truth.servo.pwm_frame_s = 0.02;
  truth.servo.pwm_frame_phase_s = 0.007;
  truth.servo.supply_sag_ohm = 8.0;
  truth.servo.supply_rail_f = 2e-3;
  const MeasuredRecord m = bench_record(truth, 11);
  std::string log[2], report[2];
  int runs[2];
  for (int paired = 0; paired < 2; ++paired) {
    set_paired_runs(paired == 1);
    const ServoCalibration c = calibrate_servo(datasheet(), m, [&](const std::string& l) { log[paired] += l + "\n"; });
    report[paired] = calibration_report_json(c).dump(1);
    runs[paired] = c.model_runs;
    if (paired == 1) {
      std::vector<std::string> names = effect_names(c.final_fit);
      std::sort(names.begin(), names.end());
      EXPECT_EQ(names, (std::vector<std::string>{"pwm_frame_delay", "supply_sag"}));
    }
  }
  std::printf("frame clock + supply sag on a rail: %d model runs, %zu lines of progress\n", runs[1],
              static_cast<size_t>(std::count(log[1].begin(), log[1].end(), '\n')));
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_EQ(report[0], report[1]);
  EXPECT_EQ(log[0], log[1]);
  // a refining form was fitted (its task ran), not only passed over
  EXPECT_NE(log[1].find("candidate supply_sag (pwm_bridge_rail) ="), std::string::npos);
}

TEST(ServoCalibration, NoEffectIsAddedWhenNoneIsMissingAndTheReportSaysSo) {
  BenchConfig truth = datasheet();
  truth.servo.kp *= 0.97;
  const ServoCalibration c = calibrate_servo(datasheet(), bench_record(truth, 8), [](const std::string&) {});
  EXPECT_EQ(c.verdict, "no_missing_effect");
  EXPECT_TRUE(c.final_fit.effects.empty());
  EXPECT_LE(c.base.white, kWhiteMax);

  const std::string dir = testing::TempDir() + "/servo_calibration_test_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  write_calibration_report(c, "", "m.csv", dir);
  std::ifstream jf(dir + "/report.json");
  const nlohmann::json j = nlohmann::json::parse(jf);
  EXPECT_EQ(j["verdict"], "no_missing_effect");
  EXPECT_TRUE(j["effects"].empty());
  EXPECT_NEAR(j["base"]["Kp"]["factor"].get<double>(), 0.97, 0.02);
  EXPECT_EQ(j["model_runs"].get<int>(), c.model_runs);
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

// The shipped bench file and set-point program with a 3 degree backlash, as
// `chainsim bench` writes it (the ODE stand at 500 us, no noise, 4 decimals)
// and `chainsim calibrate --bench` reads it. Its residual after backlash is
// the ODE stand's own difference from the fit's solver, above the white
// level of a record without noise: no catalogue effect is that difference.
TEST(ServoCalibration, TheShippedBacklashRecordNamesBacklashAlone) {
  const std::string scenes = std::string(CHAINSIM_SOURCE_DIR) + "/scenes/bench/";
  const BenchConfig sheet = load_bench_config(scenes + "servo-default.yaml");
  BenchConfig truth = sheet;
  truth.servo.backlash_deg = 3.0;
  const SetpointProgram prog = read_setpoints(scenes + "step-30-120.csv");
  const std::string dir = testing::TempDir() + "/servo_calibration_shipped_" + std::to_string(getpid());
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir + "/m.csv") << format_bench_csv(prog, simulate_bench(truth, prog.t_s, prog.setpoint_deg));
  }
  const ServoCalibration c = calibrate_servo(sheet, read_measured(dir + "/m.csv", 32), [](const std::string&) {});
  std::filesystem::remove_all(dir);
  std::printf("shipped backlash record: verdict %s, effects %zu, gap %.4f -> %.4f\n", c.verdict.c_str(),
              c.final_fit.effects.size(), c.gap_before, c.gap_after);
  ASSERT_EQ(effect_names(c.final_fit), std::vector<std::string>{"backlash"});
  EXPECT_NEAR(c.final_fit.x[kNumBase], 3.0, 0.3);
  EXPECT_LT(c.gap_after, 0.5 * c.gap_before);
}

}  // namespace
}  // namespace chainsim
