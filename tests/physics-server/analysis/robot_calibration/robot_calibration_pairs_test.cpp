// `chainsim calibrate --robot` on speed tables measured on a robot with two
// parameters changed together (issue: robot-level calibration finds two
// effects hidden together). Each case writes the changed module as its own
// module file (the shipped one with its numbers scaled in the text, not
// through the calibration's own knob code), runs it on every row's scene to
// make the "real" table, then calibrates the shipped scenes against it and
// checks that both changes are named with their factors within 10 %. The
// drive cases take about 1.5 min each; the inchworm's, about 5 min, is run
// on demand (below).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "analysis/robot_calibration/scene_runner.h"
#include "analysis/robot_calibration/scene_variants.h"

namespace chainsim {
namespace {

const std::string kSrc = CHAINSIM_SOURCE_DIR;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// every number after `key: ` in text times factor
std::string scale_numbers(std::string text, const std::string& key, double factor) {
  const std::regex re("(\\b" + key + ": )([-0-9.eE+]+)");
  std::string out;
  std::sregex_iterator it(text.begin(), text.end(), re), end;
  size_t last = 0;
  int count = 0;
  for (; it != end; ++it, ++count) {
    out += text.substr(last, size_t(it->position(0)) - last) + (*it)[1].str();
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", std::stod((*it)[2].str()) * factor);
    out += buf;
    last = size_t(it->position(0) + it->length(0));
  }
  EXPECT_GT(count, 0) << key;
  return out + text.substr(last);
}

struct Change {
  std::string type, key;   // module type (scenes/modules/<type>.yaml) and the number's key there
  double factor;
};

struct PairCase {
  std::string name;
  std::string scene;                      // a shipped scene at 30 degrees
  std::vector<std::string> slopes;
  std::vector<Change> changes;
  std::map<std::string, double> expect;   // knob name -> factor the calibration should find
  bool singles_fall_short = true;         // no single knob is accepted on the way
};

// writes nominal-<slope>.yaml, hidden-<slope>.yaml and table.csv into dir
void make_case(const PairCase& c, const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::map<std::string, std::string> types;
  for (const Change& ch : c.changes) {
    if (!types.count(ch.type)) types[ch.type] = read_text(kSrc + "/scenes/modules/" + ch.type + ".yaml");
    types[ch.type] = scale_numbers(types[ch.type], ch.key, ch.factor);
  }
  std::string module_types = "module_types:\n";
  for (const auto& [type, text] : types) {
    std::ofstream(dir + "/hidden-" + type + ".yaml") << text;
    module_types += "  " + type + ": hidden-" + type + ".yaml\n";
  }
  const std::string base = read_text(kSrc + "/scenes/" + c.scene);
  for (const std::string& slope : c.slopes) {
    std::string s = std::regex_replace(base, std::regex("slope_deg: 30"), "slope_deg: " + slope);
    std::ofstream(dir + "/nominal-" + slope + ".yaml") << s;
    const size_t at = s.find("\nchain: ");
    ASSERT_NE(at, std::string::npos);
    s.insert(at + 1, module_types);
    std::ofstream(dir + "/hidden-" + slope + ".yaml") << s;
  }
  // the "measured" speeds: the hidden robot run like any calibration run
  const SceneVariants hidden(dir + "/hidden-{slope}.yaml", c.slopes);
  SceneRunOptions opt;
  opt.chainsim_exe = CHAINSIM_EXE;
  opt.work_dir = dir + "/hidden-runs";
  opt.duration_s = 2.5;
  opt.window_start_s = 1;
  SceneRunner runner(hidden, c.slopes, opt);
  const std::vector<double> v = runner.speeds({});
  std::ofstream t(dir + "/table.csv");
  t << "# " << c.name << "\nslope_deg,real_speed_cm_s\n";
  for (size_t i = 0; i < v.size(); ++i) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s,%.2f\n", c.slopes[i].c_str(), v[i]);
    t << buf;
  }
}

nlohmann::json calibrate(const std::string& dir) {
  const std::string cmd = std::string(CHAINSIM_EXE) + " calibrate --robot " + dir + "/table.csv --scene-template '" +
                          dir + "/nominal-{slope}.yaml' --duration 2.5 --window-start 1 --out " + dir +
                          "/out --quiet";
  const int st = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << cmd;
  std::ifstream f(dir + "/out/report.json");
  EXPECT_TRUE(f) << dir;
  return f ? nlohmann::json::parse(f) : nlohmann::json();
}

void check_pair(const PairCase& c) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("chainsim-robotpair-" + c.name + "-" + std::to_string(getpid())))
          .string();
  std::filesystem::remove_all(dir);
  make_case(c, dir);
  const nlohmann::json j = calibrate(dir);
  ASSERT_TRUE(j.is_object());
  std::printf("%s: verdict %s, gap %.3f -> %.3f, %d settings, %.0f s wall\n", c.name.c_str(),
              j["verdict"].get<std::string>().c_str(), j["gap_before"].get<double>(), j["gap_after"].get<double>(),
              j["evaluations"].get<int>(), j["wall_s"].get<double>());
  for (const auto& p : j["pairs"])
    std::printf("  pair %s + %s: gap %.3f: %s\n", p["names"][0].get<std::string>().c_str(),
                p["names"][1].get<std::string>().c_str(), p["gap"].get<double>(), p["why"].get<std::string>().c_str());
  // neither change alone explains the table: no single knob was accepted
  if (c.singles_fall_short) {
    for (const auto& cand : j["candidates"])
      EXPECT_FALSE(cand["accepted"].get<bool>()) << cand["name"] << " " << cand["why"];
  }
  ASSERT_EQ(j["effects"].size(), 2u) << j["verdict"];
  for (const auto& e : j["effects"]) {
    const std::string name = e["name"];
    ASSERT_TRUE(c.expect.count(name)) << name;
    const double want = c.expect.at(name), got = e["factor"];
    std::printf("  %s x%.3f (hidden x%.3f)\n", name.c_str(), got, want);
    EXPECT_NEAR(got / want, 1.0, 0.10) << name;
  }
  EXPECT_LT(j["gap_after"].get<double>(), 0.3 * j["gap_before"].get<double>());
  EXPECT_TRUE(j["aliases"].empty());
  std::filesystem::remove_all(dir);
}

const std::vector<std::string> kSlopes = {"0", "30", "45", "60", "90"};

// a stronger, slower drive motor: 1.3 x the stall torque, 0.85 x the free speed
TEST(RobotCalibrationPairs, StrongerSlowerDrive) {
  check_pair({"stronger-slower", "helicoidal-30.yaml", kSlopes,
              {{"helicoidal", "stall_torque_nm", 1.3}, {"helicoidal", "free_speed_rad_s", 0.85}},
              {{"drive_stall", 1.3}, {"drive_free_speed", 0.85}}});
}

// a weaker, faster one: 0.75 x the stall torque, 1.2 x the free speed
TEST(RobotCalibrationPairs, WeakerFasterDrive) {
  check_pair({"weaker-faster", "helicoidal-30.yaml", kSlopes,
              {{"helicoidal", "stall_torque_nm", 0.75}, {"helicoidal", "free_speed_rad_s", 1.2}},
              {{"drive_stall", 0.75}, {"drive_free_speed", 1.2}}});
}

// the inchworm (support, extension, support; the exact solver), its drive and
// its grip changed together: the extension's stall force x0.8 and the pads'
// friction x0.85. The greedy rounds take the arms' grip torque first (the
// pads' grip seen through the force pressing them) and no second knob cuts
// the rest by 30 %; the pair stage finds the two changes and replaces it.
// About 5 minutes of two cores (the exact solver's runs): a study run on
// demand, outside the suite's quarter of an hour:
//   robot_calibration_pairs_test --gtest_also_run_disabled_tests --gtest_filter='*Inchworm*'
// (docs/calibration.md, "Two effects hidden together").
TEST(RobotCalibrationPairs, DISABLED_InchwormWeakerExtensionAndSlipperierPads) {
  check_pair({"inchworm", "inchworm-30.yaml", {"0", "15", "30", "45", "60"},
              {{"extension", "fmax_n", 0.8}, {"support", "mu", 0.85}},
              {{"extension_force", 0.8}, {"pad_friction", 0.85}},
              false});
}

}  // namespace
}  // namespace chainsim
