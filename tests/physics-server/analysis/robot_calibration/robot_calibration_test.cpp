// `chainsim calibrate --robot` (physics-server/analysis/robot_calibration) on the paper's
// Table 2 (scenes/measured/helicoidal_speed_vs_slope.csv) with the shipped
// helicoidal scenes, runs of 2.5 s: the fit must cut the gap, name an effect
// of the robot-level catalogue, and beat the paper's simulator.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
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

TEST(RobotCalibration, HelicoidalTableCutsTheGapWithANamedEffect) {
  const std::string out = tmp_dir("heli");
  ASSERT_EQ(run("--robot " + kSrc + "/scenes/measured/helicoidal_speed_vs_slope.csv --scene-template '" + kSrc +
                "/scenes/helicoidal-{slope}.yaml' --duration 2.5 --window-start 1 --out " + out),
            0);
  std::ifstream f(out + "/report.json");
  ASSERT_TRUE(f) << out;
  const auto j = nlohmann::json::parse(f);
  ASSERT_EQ(j["rows"].size(), 4u);
  const double before = j["gap_before"], after = j["gap_after"], paper = j["gap_paper_sim"];
  // the shipped model is already close (docs/firmware.md: 2.91 / 2.00 / 1.36 / 1.16 cm/s)
  EXPECT_GT(before, 0.05);
  EXPECT_LT(before, 0.2);
  EXPECT_NEAR(paper, 0.122, 0.001);
  // the fit cuts the gap by at least the acceptance threshold (30 %) and ends
  // below the paper's simulator's error
  EXPECT_LT(after, 0.7 * before);
  EXPECT_LT(after, paper);
  ASSERT_GE(j["effects"].size(), 1u);
  const std::set<std::string> catalogue = {"screw_drive_thrust", "screw_drive_free_speed", "wall_friction"};
  for (const auto& e : j["effects"]) {
    EXPECT_TRUE(catalogue.count(e["name"].get<std::string>())) << e["name"];
    EXPECT_GT(std::abs(e["factor"].get<double>() - 1.0), 0.01) << e["name"];
  }
  // the support module's knob does not apply to a helicoidal chain
  for (const auto& k : j["catalogue_applicable"]) EXPECT_NE(k.get<std::string>(), "arm_grip_torque");
  // the speeds measured with the fitted effect agree with every row within 0.15 cm/s
  for (const auto& r : j["rows"])
    EXPECT_NEAR(r["after"].get<double>(), r["real"].get<double>(), 0.15) << r["slope_deg"];
  EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
  std::filesystem::remove_all(out);
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
