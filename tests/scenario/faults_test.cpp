// Module faults: a crash, an exit, a hang, a garbage frame or a kill is reported
// by name (index, type, pid, cause, simulated time), nothing written is lost,
// and no module process outlives the server.
#include <gtest/gtest.h>

#include <signal.h>

#include <filesystem>
#include <sstream>

#include "scenario_util.h"

using namespace scenario;

namespace {

// three rotation modules and, at the tail, a module running fw-test-misbehave
std::string misbehave_scene(const std::string& dir, int mode, int at_ms, const std::string& more = "") {
  return write_file(dir, "s.yaml",
                    "name: faulty\nduration_s: 2\nchain:\n  - {type: rotation}\n  - {type: rotation}\n"
                    "  - {type: rotation}\n  - {type: rotation, firmware: " FW_MISBEHAVE
                    ", params: {mode: " + std::to_string(mode) + ", at_ms: " + std::to_string(at_ms) + "}}\n" +
                        more);
}

const nlohmann::json& module(const Outcome& o, int i) { return o.summary["modules"][i]; }

void expect_no_survivors(const Outcome& o) {
  for (const auto& m : o.summary["modules"]) {
    const pid_t pid = m["pid"].get<pid_t>();
    if (pid > 0) {
      EXPECT_FALSE(alive(pid)) << "orphan module process " << pid;
    }
  }
}

}  // namespace

TEST(Faults, KilledModuleIsReportedByNameAndLeavesNoOrphans) {
  const std::string dir = temp_dir("kill");
  const std::string err = dir + "/stderr.txt";
  const pid_t server = start_chainsim({"run", "--duration", "30", "--out", dir + "/run"}, err);
  // wait until the nine module processes run and the trace has grown a little
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return (kids = children_of(server)).size() == 9; }, 30));
  ASSERT_TRUE(wait_until([&] { return read_file(dir + "/run/trace.csv").size() > 100000; }, 60));
  pid_t victim = 0;
  for (pid_t k : kids)
    if (read_file("/proc/" + std::to_string(k) + "/environ").find(std::string("CHAINSIM_MODULE_INDEX=3\0", 24)) !=
        std::string::npos)
      victim = k;
  ASSERT_GT(victim, 0);
  ASSERT_EQ(kill(victim, SIGKILL), 0);
  const Outcome o = wait_chainsim(server, dir + "/run", err);
  EXPECT_EQ(o.exit_code, 2) << o.stderr_text;
  const std::string want = "module 3 (rotation, pid " + std::to_string(victim) + ")";
  EXPECT_NE(o.stderr_text.find(want), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("signal 9"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("at t="), std::string::npos) << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  EXPECT_NE(module(o, 3)["fault"].get<std::string>().find(want), std::string::npos);
  EXPECT_TRUE(module(o, 2)["fault"].is_null());
  EXPECT_LT(o.summary["sim_time_s"].get<double>(), 30.0);
  EXPECT_EQ(o.summary["trace_sha256"], sha256_file(o.dir + "/trace.csv"));  // the trace is complete up to the stop
  for (pid_t k : kids) EXPECT_FALSE(alive(k)) << "orphan " << k;
}

TEST(Faults, CrashingModuleStopsTheRunNamingItsSignal) {
  const std::string dir = temp_dir("crash");
  const Outcome o = run({misbehave_scene(dir, 2, 300)}, dir);
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("module 3 (rotation, pid " + std::to_string(module(o, 3)["pid"].get<int>())),
            std::string::npos)
      << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("Segmentation fault"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("at t=0.30"), std::string::npos) << o.stderr_text;
  // the module's last log line before the crash was kept
  EXPECT_NE(read_file(o.dir + "/modules/03-rotation.log").find("misbehaving now"), std::string::npos);
  expect_no_survivors(o);
}

// the tick in which the module died was stepped (the physics runs while the
// modules compute): the summary's simulated time is where the trace ends
TEST(Faults, SummaryTimeIsWhereTheTraceEnds) {
  const std::string dir = temp_dir("crash-time");
  const Outcome o = run({misbehave_scene(dir, 2, 300, "output: {trace_hz: 1000}\n")}, dir);
  EXPECT_EQ(o.exit_code, 2);
  const auto tr = read_trace(o.dir + "/trace.csv");
  ASSERT_FALSE(tr.at("t_s").empty());
  EXPECT_NEAR(tr.at("t_s").back(), o.summary["sim_time_s"].get<double>(), 1e-9);
}

TEST(Faults, HungModuleIsReportedByNameAfterTheTimeout) {
  const std::string dir = temp_dir("hang");
  const Outcome o = run({misbehave_scene(dir, 1, 200), "--module-timeout", "1"}, dir);
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("module 3 (rotation, pid"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("did not answer within 1.0 s"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("hung, or busy without a HAL wait"), std::string::npos) << o.stderr_text;
  expect_no_survivors(o);
}

// a wait on I2C that returns at once (a frame waits unread) never reaches the
// server: the hang report names that cause, not a loop without waits
TEST(Faults, AWaitThatReturnsAtOnceIsToldApartFromALoopWithoutWaits) {
  const std::string dir = temp_dir("spin");
  const Outcome o = run({misbehave_scene(dir, 6, 0), "--module-timeout", "1"}, dir);
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("did not answer within 1.0 s"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("busy in hal_wait_event_ms, which returns at once while an I2C frame waits unread"),
            std::string::npos)
      << o.stderr_text;
  expect_no_survivors(o);
}

// the lines a module logs just before it crashes or exits reach its log, and
// a crash leaves a backtrace naming the function in the module's .out file
TEST(Faults, TheLastLinesBeforeACrashAreKeptAndItsBacktraceIsNamed) {
  const std::string dir = temp_dir("last-words-crash");
  const Outcome o = run({misbehave_scene(dir, 4, 300)}, dir);
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("Segmentation fault"), std::string::npos) << o.stderr_text;
  const std::string log = read_file(o.dir + "/modules/03-rotation.log");
  EXPECT_NE(log.find("misbehaving now, mode 4"), std::string::npos) << log;
  EXPECT_NE(log.find("last words before the crash"), std::string::npos) << log;
  const std::string out_file = o.dir + "/modules/03-rotation.out";
  const std::string out = read_file(out_file);
  EXPECT_NE(out.find("backtrace of SIGSEGV"), std::string::npos) << out;
  EXPECT_NE(out.find("(crash+"), std::string::npos) << out;  // the faulting function, by name
  EXPECT_NE(out.find("(main+"), std::string::npos) << out;
  // named inside the run directory, and no address of the backtrace in the message
  EXPECT_NE(o.stderr_text.find("Segmentation fault); backtrace in modules/03-rotation.out at t="), std::string::npos)
      << o.stderr_text;
  expect_no_survivors(o);
}

TEST(Faults, TheLastLinesBeforeAnExitAreKeptAndEveryLogFileExists) {
  const std::string dir = temp_dir("last-words-exit");
  const Outcome o = run({misbehave_scene(dir, 5, 300)}, dir);
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("exit code 6"), std::string::npos) << o.stderr_text;
  const std::string log = read_file(o.dir + "/modules/03-rotation.log");
  EXPECT_NE(log.find("last words before exit"), std::string::npos) << log;
  EXPECT_EQ(read_file(o.dir + "/modules/03-rotation.out").find("backtrace"), std::string::npos);
  // the rotation modules log nothing here: their log files exist, empty
  for (int i = 0; i < 3; ++i) {
    const std::string path = o.dir + "/modules/0" + std::to_string(i) + "-rotation.log";
    EXPECT_TRUE(std::filesystem::is_regular_file(path)) << path;
  }
  expect_no_survivors(o);
}

TEST(Faults, GarbageFrameIsRejectedAndNamesTheSender) {
  const std::string dir = temp_dir("garbage");
  const std::string scene = write_file(
      dir, "s.yaml", "chain:\n  - {type: rotation}\n  - {type: rotation, firmware: " FW_GARBAGE "}\n");
  const Outcome o = run({scene, "--duration", "1"}, dir);
  EXPECT_EQ(o.exit_code, 2);
  EXPECT_NE(o.stderr_text.find("module 1 (rotation, pid"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("malformed frame"), std::string::npos) << o.stderr_text;
  expect_no_survivors(o);
}

TEST(Faults, LimpModeGoesOnWithTheModulePoweredOff) {
  const std::string dir = temp_dir("limp");
  const Outcome o = run({misbehave_scene(dir, 3, 500), "--on-module-fault=limp"}, dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  EXPECT_NEAR(o.summary["sim_time_s"].get<double>(), 2.0, 1e-9);  // the run went on to the end
  const std::string fault = module(o, 3)["fault"].get<std::string>();
  EXPECT_NE(fault.find("exit code 5"), std::string::npos) << fault;
  EXPECT_NE(fault.find("at t=0.50"), std::string::npos) << fault;
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(module(o, i)["fault"].is_null());
  EXPECT_TRUE(module(o, 4)["fault"].is_null());
  // discovery's answer: the misbehaving program never takes an address, the others do
  EXPECT_TRUE(module(o, 3)["i2c_address"].is_null()) << module(o, 3);
  EXPECT_EQ(module(o, 2)["i2c_address"], "0x22") << module(o, 2);
  expect_no_survivors(o);
}

TEST(Faults, InterruptEndsEveryModuleAndKeepsTheOutputs) {
  const std::string dir = temp_dir("sigint");
  const std::string err = dir + "/stderr.txt";
  const pid_t server = start_chainsim({"run", "--duration", "60", "--out", dir + "/run"}, err);
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return (kids = children_of(server)).size() == 9; }, 30));
  ASSERT_TRUE(wait_until([&] { return read_file(dir + "/run/trace.csv").size() > 50000; }, 60));
  kill(server, SIGINT);
  const Outcome o = wait_chainsim(server, dir + "/run", err);
  EXPECT_EQ(o.exit_code, 130) << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  EXPECT_NE(o.summary["stopped_by"].get<std::string>().find("interrupted"), std::string::npos);
  EXPECT_EQ(o.summary["trace_sha256"], sha256_file(o.dir + "/trace.csv"));
  for (pid_t k : kids) EXPECT_FALSE(alive(k)) << "orphan " << k;
}

TEST(Faults, ModulesDieWithAServerThatIsKilledOutright) {
  const std::string dir = temp_dir("sigkill");
  const std::string err = dir + "/stderr.txt";
  const pid_t server = start_chainsim({"run", "--duration", "60", "--out", dir + "/run"}, err);
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return (kids = children_of(server)).size() == 9; }, 30));
  kill(server, SIGKILL);  // no chance to clean up: the kernel must end the modules
  wait_chainsim(server, dir + "/run", err);
  for (pid_t k : kids) EXPECT_TRUE(wait_until([&] { return !alive(k); }, 5)) << "orphan " << k;
  // what was flushed before the kill is still there
  EXPECT_FALSE(read_file(dir + "/run/scene.json").empty());
}

// no process a module starts outlives the run: a child it forked (in its
// process group) nor a grandchild that left the group with setsid (adopted
// by the server, its subreaper), and the run itself goes on undisturbed
TEST(Faults, NoProcessAModuleStartedOutlivesTheRun) {
  for (int mode : {7, 8}) {
    const std::string dir = temp_dir("orphans");
    const std::string pids = dir + "/pids.txt";
    setenv("CHAINSIM_TEST_PID_FILE", pids.c_str(), 1);
    const Outcome o = run({misbehave_scene(dir, mode, 200), "--duration", "0.9"}, dir);  // before discovery is judged
    unsetenv("CHAINSIM_TEST_PID_FILE");
    EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
    std::istringstream in(read_file(pids));
    int n = 0;
    for (pid_t p; in >> p; ++n) EXPECT_FALSE(alive(p)) << "mode " << mode << ": process " << p << " outlived the run";
    EXPECT_EQ(n, 1) << "mode " << mode << ": the module's sleeper never started";
    if (mode == 8) {  // (a child in the module's group goes with the group, unannounced)
      EXPECT_NE(o.stderr_text.find(" a module left behind ended"), std::string::npos) << o.stderr_text;
    }
    expect_no_survivors(o);
  }
}
