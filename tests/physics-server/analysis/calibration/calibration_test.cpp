// `chainsim calibrate` against synthetic measurements with hidden effects
// (synth.h). For each catalogued effect the workflow must name it and shrink
// the gap by at least half; null data give no_missing_effect; two effects at
// once give both; an effect outside the catalogue gives unexplained.
#include <gtest/gtest.h>

#include <set>

#include "common.h"

namespace {

class Calibration : public ::testing::TestWithParam<int> {};

TEST_P(Calibration, FindsTheHiddenEffect) {
  const synth::Case c = synth::cases()[GetParam()];
  const std::string dir = synth::make_temp_dir();
  const synth::Outcome o = synth::calibrate_case(c, 1, dir);
  ASSERT_EQ(o.exit_code, 0) << c.name;
  const nlohmann::json& j = o.report;
  ASSERT_TRUE(j.is_object()) << c.name;
  std::vector<std::string> names;
  for (const auto& e : j["effects"]) names.push_back(e["name"]);
  const double before = j["gap_before"], after = j["gap_after"];
  SCOPED_TRACE(c.name + ": verdict " + j["verdict"].get<std::string>() + ", gap " + std::to_string(before) +
               " -> " + std::to_string(after));
  if (c.verdict == "no_missing_effect" || c.verdict == "unexplained") {
    EXPECT_EQ(j["verdict"], c.verdict);
    if (c.verdict == "no_missing_effect") {
      EXPECT_TRUE(names.empty());
    }
  } else {
    // every hidden effect is named, the first one found is a hidden one
    for (const std::string& e : c.expect)
      EXPECT_NE(std::find(names.begin(), names.end(), e), names.end()) << e << " not found";
    ASSERT_FALSE(names.empty());
    EXPECT_NE(std::find(c.expect.begin(), c.expect.end(), names.front()), c.expect.end());
    EXPECT_LE(after, 0.5 * before);
    // exactly the hidden ones, and the residual left is white
    EXPECT_EQ(std::set<std::string>(names.begin(), names.end()),
              std::set<std::string>(c.expect.begin(), c.expect.end()));
    EXPECT_EQ(j["verdict"], "explained");
    // the two effects whose models differed from the generator's until the
    // fit's second start and the plastic gap closing: their values too
    for (const auto& e : j["effects"]) {
      if (e["name"] == "coulomb_friction")
        EXPECT_NEAR(e["params"]["torque_nm"].get<double>(), c.truth.coulomb, 0.1 * c.truth.coulomb);
      if (e["name"] == "backlash")
        EXPECT_NEAR(e["params"]["width_deg"].get<double>(), c.truth.backlash_deg, 0.15 * c.truth.backlash_deg);
    }
  }
  std::system(("rm -rf '" + dir + "'").c_str());
}

INSTANTIATE_TEST_SUITE_P(Cases, Calibration, ::testing::Range(0, static_cast<int>(synth::cases().size())),
                         [](const auto& info) {
                           std::string n = synth::cases()[info.param].name;
                           std::string out;
                           for (char ch : n)
                             if (std::isalnum(static_cast<unsigned char>(ch))) out += ch;
                             else if (!out.empty() && out.back() != '_') out += '_';
                           while (!out.empty() && out.back() == '_') out.pop_back();
                           return out;
                         });

TEST(CalibrationFiles, ErrorsNameFileLineColumn) {
  const std::string dir = synth::make_temp_dir();
  std::ofstream(dir + "/m.csv") << "t_s,setpoint_deg,angle_deg\n0,30,30\n0.001,30,3x0\n";
  const std::string cmd = std::string("'") + CHAINSIM_EXE + "' calibrate --measured '" + dir + "/m.csv' --out '" +
                          dir + "/out' 2> '" + dir + "/err.txt'";
  const int st = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(st), 1);
  std::ifstream in(dir + "/err.txt");
  std::string err((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(err.find("m.csv:3:10: '3x0' in column 'angle_deg' is not a number"), std::string::npos) << err;
  std::system(("rm -rf '" + dir + "'").c_str());
}

}  // namespace
