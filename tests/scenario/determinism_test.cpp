// Same scene and seed, same bytes: whatever the machine load, and whether a
// module is spawned by the server or started by hand.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <regex>

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
  EXPECT_EQ(read_file(a.dir + "/trace.csv"), read_file(b.dir + "/trace.csv"));
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
