// `chainsim bench-lockstep`: the price of processes and sockets, measured on
// the built-in chains or on scene files (--scene), each co-simulation's
// servo commands replayed into a world with no processes. Figures are
// wall-clock and are not asserted; what is asserted is that every scene is
// measured, its replay gives its co-simulation's trace byte for byte, and
// bad input is named before anything runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "scenario_util.h"

using namespace scenario;

namespace {

struct Row {
  std::string scene, target, same_trace;
  int modules = -1;
  double sim_s = 0, cosim_rtf = 0, physics_rtf = 0, ratio = 0, cpu_ratio = 0, modules_cpu_s = -1, exch_per_tick = -1;
};

// the table's row of a scene (scene == "" when it has none)
Row row_of(const std::string& out, const std::string& scene) {
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream f(line);
    Row r;
    if (f >> r.scene && r.scene == scene &&
        f >> r.target >> r.modules >> r.sim_s >> r.cosim_rtf >> r.physics_rtf >> r.ratio >> r.cpu_ratio >> r.modules_cpu_s >>
            r.exch_per_tick >> r.same_trace)
      return r;
  }
  return Row{};
}

}  // namespace

TEST(BenchLockstep, ScenesAreMeasuredAndTheirReplaysGiveTheirTraces) {
  const std::string dir = temp_dir("bench-lockstep-scenes");
  const auto [out, rc] = chainsim_stdout("bench-lockstep --scene " + scene_path("helicoidal-0") + " " +
                                         scene_path("inchworm-0") + " --duration 0.5 --repeat 2 --out " + dir);
  ASSERT_EQ(rc, 0) << out;
  const Row h = row_of(out, "helicoidal-0"), w = row_of(out, "inchworm-0");
  ASSERT_EQ(h.scene, "helicoidal-0") << out;
  ASSERT_EQ(w.scene, "inchworm-0") << out;
  EXPECT_EQ(h.modules, 1);
  EXPECT_EQ(w.modules, 3);
  for (const Row& r : {h, w}) {
    EXPECT_EQ(r.target, "native");
    EXPECT_DOUBLE_EQ(r.sim_s, 0.5);
    EXPECT_GT(r.cosim_rtf, 0);
    EXPECT_GT(r.physics_rtf, 0);
    EXPECT_NEAR(r.ratio, r.physics_rtf / r.cosim_rtf, 0.01 * r.ratio + 0.002);
    // the server does at least the replay's work: its CPU is not below the
    // replay's by more than the clocks' grain
    EXPECT_GT(r.cpu_ratio, 0.8) << out;
    EXPECT_EQ(r.same_trace, "yes") << out;
  }
  // the module processes' CPU is counted: three programs and the central
  // control ran half a second of firmware each
  EXPECT_GT(w.modules_cpu_s, 0.0) << out;
  // the inchworm's modules compute every 10 ms (S E S and the central control)
  EXPECT_GT(w.exch_per_tick, 0.05);
  // each scene's last co-simulation is kept, as long as --duration asked
  for (const char* run : {"/0-helicoidal-0", "/1-inchworm-0"}) {
    const auto summary = nlohmann::json::parse(read_file(dir + run + "/summary.json"));
    EXPECT_DOUBLE_EQ(summary["sim_time_s"].get<double>(), 0.5) << run;
  }
}

TEST(BenchLockstep, ChainsOfRotationModulesAsBefore) {
  const std::string dir = temp_dir("bench-lockstep-chains");
  const auto [out, rc] = chainsim_stdout("bench-lockstep --modules 2 --duration 0.2 --repeat 1 --out " + dir);
  ASSERT_EQ(rc, 0) << out;
  const Row r = row_of(out, "bench-2");
  EXPECT_EQ(r.modules, 2) << out;
  EXPECT_DOUBLE_EQ(r.sim_s, 0.2);
  EXPECT_EQ(r.same_trace, "yes");
  EXPECT_GT(r.exch_per_tick, 0);
}

TEST(BenchLockstep, BadScenesAndDurationsAreNamedBeforeAnythingRuns) {
  const std::string dir = temp_dir("bench-lockstep-bad");
  const std::string bad = write_file(dir, "bad.yaml", "name: bad\nduration_s: 1\nchain: RRX\n");
  const auto [out, rc] = chainsim_stdout("bench-lockstep --scene " + scene_path("helicoidal-0") + " " + bad +
                                         " --repeat 1 --out " + dir + "/runs");
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find(bad), std::string::npos) << out;
  EXPECT_EQ(row_of(out, "helicoidal-0").scene, "") << out;  // the good scene did not run either
  EXPECT_FALSE(std::filesystem::exists(dir + "/runs")) << out;

  const auto [out2, rc2] = chainsim_stdout("bench-lockstep --scene " + scene_path("helicoidal-0") +
                                           " --duration 0.0001 --out " + dir + "/runs");
  EXPECT_EQ(rc2, 1) << out2;
  EXPECT_NE(out2.find(scene_path("helicoidal-0") +
                      ": --duration 0.000100 s is shorter than one tick of the scene (physics.tick_us = 1000 us)"),
            std::string::npos)
      << out2;

  const auto [out3, rc3] = chainsim_stdout("bench-lockstep --scene " + dir + "/missing.yaml");
  EXPECT_EQ(rc3, 1) << out3;
  EXPECT_NE(out3.find("missing.yaml"), std::string::npos) << out3;

  // the chains' options do not mix with scene files
  const auto [out4, rc4] = chainsim_stdout("bench-lockstep --scene " + scene_path("helicoidal-0") + " --modules 2");
  EXPECT_EQ(rc4, 1) << out4;
  EXPECT_NE(out4.find("excludes"), std::string::npos) << out4;
}
