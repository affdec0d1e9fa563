// A module that connects but never answers discovery: judged at the scene's
// central.discovery_s (default 1 s), a named failure with exit code 6 and
// the run stopped there; not judged in a run that ends before that; no
// failure when the scene says the module may stay silent. fw-test-misbehave
// with mode 0 is such a module (it sleeps and never takes part).
#include <gtest/gtest.h>

#include <string>

#include "scenario_util.h"

using namespace scenario;

namespace {

// R, the silent module, R, R: discovery stops at module 1, so 2 and 3 get no address either
std::string silent_scene(const std::string& dir, const std::string& duration, const std::string& more = "",
                         const std::string& silent_keys = "") {
  return write_file(dir, "s.yaml",
                    "name: silent\nduration_s: " + duration + "\nchain:\n  - {type: rotation}\n"
                    "  - {type: rotation, firmware: " FW_MISBEHAVE + silent_keys + "}\n"
                    "  - {type: rotation}\n  - {type: rotation}\n" + more);
}

std::vector<int> ints(const nlohmann::json& j) { return j.get<std::vector<int>>(); }

}  // namespace

TEST(DiscoverySilent, ModuleThatNeverAnswersIsExitCode6ByName) {
  const std::string dir = temp_dir("silent");
  const Outcome o = run({silent_scene(dir, "3")}, dir);
  EXPECT_EQ(o.exit_code, 6) << o.stderr_text;
  const std::string pid = std::to_string(o.summary["modules"][1]["pid"].get<int>());
  const std::string want = "module 1 (rotation, pid " + pid + ") did not answer discovery: it has no I2C address "
                           "(judged at central.discovery_s); modules 2 and 3 after it have none either; a module "
                           "that takes no part in discovery says may_stay_silent: true in the scene at t=1.000000 s";
  EXPECT_NE(o.stderr_text.find("chainsim: run stopped: " + want), std::string::npos) << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  EXPECT_EQ(o.summary["exit_code"], 6);
  EXPECT_EQ(o.summary["stopped_by"], want);
  EXPECT_EQ(o.summary["modules"][1]["fault"], want);
  EXPECT_DOUBLE_EQ(o.summary["sim_time_s"].get<double>(), 1.0);  // stopped when judged
  EXPECT_EQ(o.summary["discovery"]["judged"], true);
  EXPECT_EQ(ints(o.summary["discovery"]["silent"]), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(o.summary["modules"][0]["i2c_address"], "0x20");
  EXPECT_TRUE(o.summary["modules"][1]["i2c_address"].is_null());
  // the same as structured events, and in bus.log as the viewer reads it
  const std::string events = read_file(o.dir + "/events.jsonl");
  EXPECT_NE(events.find("{\"t_s\":1.000000,\"event\":\"discovery\",\"answered\":[0],\"allowed_silent\":[],"
                        "\"silent\":[1,2,3]}\n"),
            std::string::npos)
      << events;
  EXPECT_NE(events.find("{\"t_s\":1.000000,\"event\":\"fault\",\"endpoint\":1,\"type\":\"rotation\",\"message\":\"" +
                        want + "\"}\n"),
            std::string::npos)
      << events;
  EXPECT_NE(read_file(o.dir + "/bus.log").find("1000000 fault " + want + "\n"), std::string::npos);
}

// a run that ends before discovery could be judged is no failure: the rule
// is the scene's central.discovery_s, not the run's length
TEST(DiscoverySilent, RunEndingBeforeTheJudgementIsNoFailure) {
  const std::string dir = temp_dir("silent-short");
  const Outcome o = run({silent_scene(dir, "0.5"), "-q"}, dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  EXPECT_EQ(o.summary["discovery"]["judged"], false);
  EXPECT_TRUE(o.summary["modules"][1]["fault"].is_null());
  EXPECT_EQ(read_file(o.dir + "/events.jsonl").find("\"discovery\""), std::string::npos);
}

// central.discovery_s moves the judgement: earlier here
TEST(DiscoverySilent, TheSceneSetsWhenDiscoveryIsJudged) {
  const std::string dir = temp_dir("silent-early");
  const Outcome o = run({silent_scene(dir, "0.5", "central: {discovery_s: 0.3}\n"), "-q"}, dir);
  EXPECT_EQ(o.exit_code, 6) << o.stderr_text;
  EXPECT_DOUBLE_EQ(o.summary["sim_time_s"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(o.summary["discovery"]["judged_at_s"].get<double>(), 0.3);
}

// the scene says the module takes no part: no failure; the modules after it
// still have no address (the central control stops at the first silent
// one), so they may stay silent too
TEST(DiscoverySilent, ModulesThatMayStaySilentAreNoFailure) {
  const std::string dir = temp_dir("silent-ok");
  const Outcome o = run({silent_scene(dir, "1.5", "programs: {rotation: {may_stay_silent: true}}\n"), "-q"}, dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  EXPECT_EQ(o.summary["discovery"]["judged"], true);
  EXPECT_EQ(ints(o.summary["discovery"]["allowed_silent"]), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(o.summary["discovery"]["silent"].empty());
  // one module's own key: only it may stay silent, the ones after it fail
  const std::string dir2 = temp_dir("silent-own");
  const Outcome o2 = run({silent_scene(dir2, "1.5", "", ", may_stay_silent: true"), "-q"}, dir2);
  EXPECT_EQ(o2.exit_code, 6) << o2.stderr_text;
  EXPECT_EQ(ints(o2.summary["discovery"]["allowed_silent"]), (std::vector<int>{1}));
  EXPECT_EQ(ints(o2.summary["discovery"]["silent"]), (std::vector<int>{2, 3}));
  EXPECT_NE(o2.summary["stopped_by"].get<std::string>().find("module 2 (rotation, pid "), std::string::npos);
}

// with --on-module-fault=limp a silent module is powered off and the run goes on, as after any fault
TEST(DiscoverySilent, LimpModeRecordsTheFaultAndGoesOn) {
  const std::string dir = temp_dir("silent-limp");
  const Outcome o = run({silent_scene(dir, "1.5"), "--on-module-fault=limp", "-q"}, dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  EXPECT_DOUBLE_EQ(o.summary["sim_time_s"].get<double>(), 1.5);
  for (int m : {1, 2, 3})
    EXPECT_NE(o.summary["modules"][m]["fault"].get<std::string>().find("did not answer discovery"), std::string::npos);
}
