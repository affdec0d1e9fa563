// `chainsim calibrate --robot` (physics-server/analysis/robot_calibration) on
// the paper's Table 2 (scenes/measured/helicoidal_speed_vs_slope.csv), runs of
// 2.5 s: the shipped helicoidal module (fitted on the table's 0 and 90 degree
// rows) needs no effect; a module whose drive motor is 30 % too weak is found
// out: the fit names the drive's stall torque, cuts the gap and beats the
// paper's simulator.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

namespace {

const std::string kSrc = CHAINSIM_SOURCE_DIR;

int run(const std::string& args) {
  const std::string cmd = std::string(CHAINSIM_EXE) + " calibrate " + args + " --quiet";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string tmp_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("chainsim-robotcal-" + name + "-" + std::to_string(getpid()));
  std::filesystem::remove_all(d);
  return d.string();
}

TEST(RobotCalibration, ShippedHelicoidalNeedsNoEffect) {
  const std::string out = tmp_dir("heli-shipped");
  ASSERT_EQ(run("--robot " + kSrc + "/scenes/measured/helicoidal_speed_vs_slope.csv --scene-template '" + kSrc +
                "/scenes/helicoidal-{slope}.yaml' --duration 2.5 --window-start 1 --out " + out),
            0);
  std::ifstream f(out + "/report.json");
  ASSERT_TRUE(f) << out;
  const auto j = nlohmann::json::parse(f);
  // docs/firmware.md: 3.00 / 2.09 / 1.44 / 1.20 cm/s over 1..6 s
  EXPECT_LT(j["gap_before"].get<double>(), 0.06);
  EXPECT_EQ(j["verdict"], "no_missing_effect");
  for (const auto& k : j["catalogue_applicable"]) EXPECT_NE(k.get<std::string>(), "arm_grip_torque");
  std::filesystem::remove_all(out);
}

TEST(RobotCalibration, AWeakDriveMotorIsFoundOut) {
  const std::string out = tmp_dir("heli-weak");
  const std::string dir = tmp_dir("heli-weak-scenes");
  std::filesystem::create_directories(dir);
  {  // the shipped module with 0.7 x its stall torque, and the scenes using it
    std::ifstream in(kSrc + "/scenes/modules/helicoidal.yaml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key = "stall_torque_nm: ";
    const size_t at = text.find(key);
    ASSERT_NE(at, std::string::npos);
    const size_t end = text.find_first_of(" \n", at + key.size());
    const double nominal = std::stod(text.substr(at + key.size(), end - at - key.size()));
    text.replace(at + key.size(), end - at - key.size(), std::to_string(0.7 * nominal));
    std::ofstream(dir + "/weak.yaml") << text;
    for (const char* slope : {"0", "30", "60", "90"}) {
      std::ifstream sc(kSrc + "/scenes/helicoidal-" + slope + ".yaml");
      std::string s((std::istreambuf_iterator<char>(sc)), std::istreambuf_iterator<char>());
      const size_t c = s.find("\nchain: H");
      ASSERT_NE(c, std::string::npos);
      s.insert(c + 1, "module_types:\n  helicoidal: weak.yaml\n");
      std::ofstream(dir + "/helicoidal-" + slope + ".yaml") << s;
    }
  }
  ASSERT_EQ(run("--robot " + kSrc + "/scenes/measured/helicoidal_speed_vs_slope.csv --scene-template '" + dir +
                "/helicoidal-{slope}.yaml' --duration 2.5 --window-start 1 --out " + out),
            0);
  std::ifstream f(out + "/report.json");
  ASSERT_TRUE(f) << out;
  const auto j = nlohmann::json::parse(f);
  ASSERT_EQ(j["rows"].size(), 4u);
  const double before = j["gap_before"], after = j["gap_after"], paper = j["gap_paper_sim"];
  EXPECT_GT(before, 0.2);
  EXPECT_NEAR(paper, 0.122, 0.001);
  EXPECT_LT(after, 0.06);
  ASSERT_GE(j["effects"].size(), 1u);
  EXPECT_EQ(j["effects"][0]["name"], "drive_stall");
  // 1 / 0.7 = 1.43 restores the shipped motor
  EXPECT_NEAR(j["effects"][0]["factor"].get<double>(), 1.43, 0.12);
  for (const auto& r : j["rows"])
    EXPECT_NEAR(r["after"].get<double>(), r["real"].get<double>(), 0.1) << r["slope_deg"];
  EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
  std::filesystem::remove_all(out);
  std::filesystem::remove_all(dir);
}

TEST(RobotCalibration, BadInputsExitWithOne) {
  const std::string out = tmp_dir("bad");
  const std::string table = kSrc + "/scenes/measured/helicoidal_speed_vs_slope.csv";
  EXPECT_EQ(run("--robot " + table + " --scene-template " + kSrc + "/scenes/helicoidal-30.yaml --out " + out), 1);
  EXPECT_EQ(run("--robot " + table + " --scene-template '" + kSrc + "/scenes/nothere-{slope}.yaml' --out " + out), 1);
  EXPECT_EQ(run("--robot " + table + " --scene-template '" + kSrc +
                "/scenes/helicoidal-{slope}.yaml' --duration 1 --window-start 1 --out " + out),
            1);
  EXPECT_NE(run("--robot " + table + " --out " + out), 0);  // no template
  std::filesystem::remove_all(out);
}

}  // namespace
