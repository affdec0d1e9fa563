// `chainsim calibrate` against synthetic measurements with hidden effects
// (synth_cases.h), a few seeds of a few cases (calibration_study runs them
// all, docs/calibration.md): each must come out exactly right (the hidden
// effects and nothing else, the expected verdict and form), with the gap at
// least halved when explained.
#include <gtest/gtest.h>

#include "common.h"

namespace {

struct Pick {
  const char* name;   // the case
  unsigned seed;
  bool plain;         // 1 kHz without jitter; else the study's conditions of the seed
};

// the study's conditions of these seeds: 100 noise 1, load 2e-5, 321 Hz;
// 101 noise 2, load 2e-5, 220 Hz; 103 noise 1, 440 Hz, angle only
const Pick kPicks[] = {
    {"null", 101, false},
    {"pwm_frame_delay", 100, false},
    {"deadband", 103, false},
    {"backlash+supply_sag", 1, true},
    {"B: supply_sag (linear driver, rail capacitor)", 101, false},
    {"B: supply_sag (PWM bridge, rail capacitor)", 100, false},
    {"cogging (outside the catalogue)", 1, true},
    {"B: pwm_frame_delay (falling edge)", 100, false},
};

class Calibration : public ::testing::TestWithParam<Pick> {};

TEST_P(Calibration, NamesExactlyTheHiddenEffects) {
  const Pick pk = GetParam();
  const synth::Case c = synth::case_named(pk.name);
  ASSERT_FALSE(c.name.empty()) << pk.name;
  const synth::Conditions cond = pk.plain ? synth::plain_conditions() : synth::conditions(pk.seed);
  const std::string dir = synth::make_temp_dir();
  const synth::Outcome o = synth::calibrate_case(c, pk.seed, cond, dir);
  ASSERT_EQ(o.exit_code, 0) << c.name;
  const nlohmann::json& j = o.report;
  ASSERT_TRUE(j.is_object()) << c.name;
  const double before = j["gap_before"], after = j["gap_after"];
  std::string found;
  for (const auto& n : o.names) found += " " + n;
  SCOPED_TRACE(c.name + " seed " + std::to_string(pk.seed) + " (" + std::to_string(cond.sample_hz) + " Hz" +
               (cond.current ? "" : ", angle only") + "): verdict " + j["verdict"].get<std::string>() + "," + found +
               ", gap " + std::to_string(before) + " -> " + std::to_string(after));
  // an effect outside the catalogue: the verdict says so (effects that
  // mimic part of it may be named; issue 14's target is the verdict)
  if (c.verdict == "unexplained") {
    EXPECT_EQ(j["verdict"], "unexplained");
  } else {
    EXPECT_TRUE(synth::exactly_right(c, o));
  }
  for (const auto& [effect, form] : c.variant) {
    if (o.variants.count(effect)) {
      EXPECT_EQ(o.variants.at(effect), form) << effect;
    }
  }
  if (j["verdict"] == "explained") {
    EXPECT_LE(after, 0.5 * before);
  }
  // a frame clock: the fitted period and phase hold the truth within their intervals
  const synth::Truth t = c.truth(pk.seed, cond);
  for (const auto& e : j["effects"]) {
    if (e["name"] != "pwm_frame_delay") continue;
    const double period = t.frame_s * 1e3, phase = t.frame_phase_s * 1e3;
    EXPECT_NEAR(e["params"]["frame_ms"].get<double>(), period, 0.05);
    EXPECT_NEAR(e["params"]["phase_ms"].get<double>(), phase, 0.5);
    // the falling-edge form: the pulse's slope within a fifth of the truth
    if (t.pulse_s_per_deg > 0) {
      EXPECT_NEAR(e["params"]["pulse_us_per_deg"].get<double>(), t.pulse_s_per_deg * 1e6, 0.2 * t.pulse_s_per_deg * 1e6);
    }
    // each accepted effect has its evidence plot
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + e["evidence"]["plot"].get<std::string>()));
  }
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Cases, Calibration, ::testing::ValuesIn(kPicks), [](const auto& info) {
  std::string out;
  for (const char* p = info.param.name; *p; ++p)
    if (std::isalnum(static_cast<unsigned char>(*p))) out += *p;
    else if (!out.empty() && out.back() != '_') out += '_';
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out + "_" + std::to_string(info.param.seed);
});

// the study's effect size: 0 for an effect the truth does not have, larger
// for a current limit set lower (it acts on more of the moves), and the
// noiseless record it compares is the noisy one without its noise: the two
// differ by about the meter's sd
TEST(EffectSize, MeasuresWhatTheEffectChangesInTheRecord) {
  const synth::Case c = synth::case_named("current_limit");
  const synth::Conditions cond = synth::plain_conditions();
  synth::Truth t = c.truth(1, cond);
  ASSERT_GT(t.ilim, 0.0);
  EXPECT_EQ(synth::effect_size(c, t, 1, "deadband"), 0.0);
  t.ilim = 0.25;
  const double high = synth::effect_size(c, t, 1, "current_limit");
  t.ilim = 0.15;
  const double low = synth::effect_size(c, t, 1, "current_limit");
  std::printf("current limit 0.25 A: size %.0f; 0.15 A: %.0f\n", high, low);
  EXPECT_GT(high, 0.0);
  EXPECT_GT(low, 2 * high);
  EXPECT_THROW(synth::effect_size(c, t, 1, "cogging"), std::invalid_argument);
  const synth::Series noisy = c.record(t, 1), exact = synth::exact_record(c, t, 1);
  ASSERT_EQ(noisy.t, exact.t);
  double ss = 0;
  for (size_t k = 0; k < noisy.t.size(); ++k) ss += std::pow(noisy.angle[k] - exact.angle[k], 2);
  const double sd = std::sqrt(ss / static_cast<double>(noisy.t.size()));
  EXPECT_NEAR(sd, synth::Meter(t).angle_sd(), 0.2 * synth::Meter(t).angle_sd());
  EXPECT_EQ(synth::weakest_effect_size(synth::case_named("null"), 1, cond), -1.0);
}

TEST(CalibrationFiles, ErrorsNameFileLineColumn) {
  const std::string dir = synth::make_temp_dir();
  std::ofstream(dir + "/m.csv") << "t_s,setpoint_deg,angle_deg\n0,30,30\n0.001,30,3x0\n";
  double cpu = 0;
  const int rc = synth::run_process({CHAINSIM_EXE, "calibrate", "--measured", dir + "/m.csv", "--out", dir + "/out"},
                                    dir + "/err.txt", &cpu);
  EXPECT_EQ(rc, 1);
  std::ifstream in(dir + "/err.txt");
  std::string err((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(err.find("m.csv:3:10: '3x0' in column 'angle_deg' is not a number"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
