// ChildProcess with real processes (/bin/sh): exit codes and signals in
// words, output capture, exec failures, waiting for one or any of several,
// and no process left behind.
#include "cosim/child_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace chainsim {
namespace {

ChildSpec sh(const std::string& script, const std::string& out = "") {
  ChildSpec s;
  s.program = "/bin/sh";
  s.args = {"-c", script};
  s.stdout_path = out;
  return s;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ChildProcess, WaitGivesTheExitCodeOrTheSignal) {
  ChildProcess a;
  a.spawn(sh("exit 3"));
  const ExitStatus& s = a.wait();
  EXPECT_TRUE(s.exited);
  EXPECT_EQ(s.code, 3);
  EXPECT_EQ(s.text(), "exit code 3");
  EXPECT_FALSE(a.running());
  ChildProcess b;
  b.spawn(sh("kill -9 $$"));
  EXPECT_FALSE(b.wait().exited);
  EXPECT_EQ(b.wait().signal, 9);
  EXPECT_NE(b.wait().text().find("signal 9"), std::string::npos);
}

TEST(ChildProcess, OutputAndErrorsGoToTheOutputFile) {
  const std::string out = testing::TempDir() + "/child_process_test.out";
  std::remove(out.c_str());
  ChildProcess a;
  a.spawn(sh("echo to-stdout; echo to-stderr >&2", out));
  EXPECT_EQ(a.wait().code, 0);
  EXPECT_EQ(slurp(out), "to-stdout\nto-stderr\n");
  ChildProcess b;
  ChildSpec bad;
  bad.program = "/no/such/program";
  bad.stdout_path = out;
  b.spawn(bad);
  EXPECT_EQ(b.wait().code, 127);
  EXPECT_NE(slurp(out).find("cannot execute /no/such/program"), std::string::npos) << slurp(out);
  std::remove(out.c_str());
}

TEST(ChildProcess, WaitWithoutAProcessIsAnError) {
  ChildProcess a;
  EXPECT_THROW(a.wait(), std::logic_error);
}

// the first child cannot end before the test lets it (a file appears), so
// which one wait_any returns does not depend on timing
TEST(ChildProcess, WaitAnyReturnsTheOneThatEnded) {
  const std::string gate = testing::TempDir() + "/child_process_test.gate";
  std::remove(gate.c_str());
  ChildProcess held, quick;
  held.spawn(sh("while [ ! -e '" + gate + "' ]; do sleep 0.01; done; exit 4"));
  quick.spawn(sh("exit 5"));
  const std::vector<ChildProcess*> both = {&held, &quick};
  EXPECT_EQ(wait_any(both), 1);
  EXPECT_EQ(quick.poll()->code, 5);
  EXPECT_TRUE(held.running());
  std::ofstream(gate) << "go";
  EXPECT_EQ(wait_any(both), 0);
  EXPECT_EQ(held.poll()->code, 4);
  EXPECT_EQ(wait_any(both), -1);  // none running
  std::remove(gate.c_str());
}

TEST(ChildProcess, DestructorEndsARunningChild) {
  pid_t pid = -1;
  {
    ChildProcess a;
    a.spawn(sh("sleep 60"));
    pid = a.pid();
    ASSERT_GT(pid, 0);
    EXPECT_EQ(kill(pid, 0), 0);
  }
  EXPECT_EQ(kill(pid, 0), -1);  // reaped: no such process
  EXPECT_EQ(errno, ESRCH);
}

}  // namespace
}  // namespace chainsim
