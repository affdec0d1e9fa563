// Same scene and seed, same bytes: whatever the machine load, whether a
// module is spawned by the server or started by hand, and whether the CPU has
// the FMA instructions that glibc's faster libm variants use.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <regex>
#include <string>

#include "scenario_util.h"

using namespace scenario;

TEST(Determinism, SameSceneAndSeedGiveTheSameTraceEvenBesideACpuHog) {
  const std::string dir = temp_dir("det");
  const Outcome a = run({"--duration", "3", "--seed", "7"}, dir + "/a");
  ASSERT_EQ(a.exit_code, 0) << a.stderr_text;
  // a second run while two busy processes compete for both cores
  std::vector<pid_t> hogs;
  for (int i = 0; i < 2; ++i) {
    const pid_t h = fork();
    if (h == 0) {
      alarm(120);  // never outlives the test
      volatile unsigned long x = 0;
      for (;;) x = x + 1;
    }
    hogs.push_back(h);
  }
  const Outcome b = run({"--duration", "3", "--seed", "7"}, dir + "/b");
  for (pid_t h : hogs) {
    kill(h, SIGKILL);
    waitpid(h, nullptr, 0);
  }
  ASSERT_EQ(b.exit_code, 0) << b.stderr_text;
  EXPECT_EQ(a.summary["trace_sha256"], b.summary["trace_sha256"]);
  EXPECT_TRUE(read_file(a.dir + "/trace.csv") == read_file(b.dir + "/trace.csv")) << a.dir << " and " << b.dir;
  EXPECT_EQ(read_file(a.dir + "/bus.log"), read_file(b.dir + "/bus.log"));
}

TEST(Determinism, ModuleStartedByHandGivesTheSameTrace) {
  const std::string dir = temp_dir("attach");
  const Outcome ref = run({"--duration", "1"}, dir + "/ref");
  ASSERT_EQ(ref.exit_code, 0) << ref.stderr_text;

  const std::string err = dir + "/stderr.txt";
  const pid_t server = start_chainsim({"run", "--duration", "1", "--attach", "2", "--out", dir + "/run"}, err);
  // the server prints the environment to start module 2 with
  std::smatch m;
  std::string text;
  const std::regex re("CHAINSIM_SOCKET=(\\S+) CHAINSIM_MODULE_INDEX=2 CHAINSIM_MODULE_TYPE=rotation gdb (\\S+)");
  ASSERT_TRUE(wait_until([&] { text = read_file(err); return std::regex_search(text, m, re); }, 30)) << text;
  const std::string sock = m[1], prog = m[2];
  usleep(300000);  // the others are connected and waiting: nothing moves without module 2
  const pid_t by_hand = fork();
  if (by_hand == 0) {
    setenv("CHAINSIM_SOCKET", sock.c_str(), 1);
    setenv("CHAINSIM_MODULE_INDEX", "2", 1);
    setenv("CHAINSIM_MODULE_TYPE", "rotation", 1);
    execl(prog.c_str(), prog.c_str(), nullptr);
    _exit(127);
  }
  const Outcome o = wait_chainsim(server, dir + "/run", err);
  waitpid(by_hand, nullptr, 0);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  EXPECT_EQ(o.summary["trace_sha256"], ref.summary["trace_sha256"]);
}

namespace {

// the default scene for 3 s (long enough for the variants' last bits to
// reach the trace), on this CPU (hwcaps nullptr) or as on one without some
// of its instructions: "-FMA" as without FMA, whose glibc has no FMA variants
// to give (chainsim itself hides them through AVX2); "-AVX" as without AVX,
// which leaves glibc the SSE2 variants where chainsim's tunable leaves the
// AVX ones (the same C code)
Outcome default_scene(const std::string& dir, const char* hwcaps) {
  const std::string t = std::string("glibc.cpu.hwcaps=") + (hwcaps ? hwcaps : "");
  EnvForChildren e("GLIBC_TUNABLES", hwcaps ? t.c_str() : nullptr);
  return run({"--duration", "3", "--seed", "7"}, dir);
}

}  // namespace

TEST(Determinism, TheTraceIsTheSameOnACpuWithoutTheFmaVariantsOfLibm) {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("fma") || !__builtin_cpu_supports("avx2"))
    GTEST_SKIP() << "this CPU has no FMA and AVX2: glibc gives every process the baseline libm here, so there is no "
                    "other variant to compare with";
  const std::string dir = temp_dir("det-libm");
  std::string machine_baseline_trace;
  // first that the test can see a difference: with the machine's own
  // variants (CHAINSIM_LIBM=machine) the two traces differ
  {
    EnvForChildren machine("CHAINSIM_LIBM", "machine");
    const Outcome a = default_scene(dir + "/machine-fma", nullptr);
    const Outcome b = default_scene(dir + "/machine-baseline", "-FMA");
    machine_baseline_trace = read_file(b.dir + "/trace.csv");
    ASSERT_EQ(a.exit_code, 0) << a.stderr_text;
    ASSERT_EQ(b.exit_code, 0) << b.stderr_text;
    ASSERT_NE(a.summary["trace_sha256"], b.summary["trace_sha256"])
        << "the FMA variants no longer change this run's trace: choose a longer run for this test";
  }
  // by default chainsim restarts itself with the baseline variants: the same
  // bytes whichever the CPU offers, and those of the baseline run above
  EnvForChildren unset("CHAINSIM_LIBM", nullptr);
  const Outcome a = default_scene(dir + "/fma", nullptr);
  const Outcome b = default_scene(dir + "/baseline", "-FMA");
  const Outcome c = default_scene(dir + "/sse2", "-AVX");
  for (const Outcome* o : {&a, &b, &c}) ASSERT_EQ(o->exit_code, 0) << o->stderr_text;
  for (const Outcome* o : {&b, &c}) {
    EXPECT_TRUE(read_file(a.dir + "/trace.csv") == read_file(o->dir + "/trace.csv")) << a.dir << " and " << o->dir;
    EXPECT_EQ(read_file(a.dir + "/bus.log"), read_file(o->dir + "/bus.log"));
  }
  EXPECT_TRUE(read_file(a.dir + "/trace.csv") == machine_baseline_trace) << "not the baseline variants' trace";
  EXPECT_EQ(a.stderr_text, "");
}
