// ChildProcess with real processes (/bin/sh): exit codes and signals in
// words, waiting for one or any of several, the output file, the environment, its own process group, the end
// of a process that ignores SIGTERM, a program that cannot be executed, and
// death with the parent.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "cosim/child_process.h"
#include "temp_dir.h"

namespace chainsim {
namespace {

namespace fs = std::filesystem;

struct TempDir : chainsim_test::TempDir {
  TempDir() : chainsim_test::TempDir("chainsim-child") {}
};

std::string read_file(const std::string& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

ChildSpec shell(const std::string& script, const std::string& out = "") {
  ChildSpec s;
  s.program = "/bin/sh";
  s.args = {"-c", script};
  s.stdout_path = out;
  return s;
}

// alive and not a zombie
bool alive(pid_t pid) {
  if (kill(pid, 0) != 0) return false;
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  std::getline(in, stat);
  const auto close = stat.rfind(')');
  return close != std::string::npos && stat[close + 2] != 'Z';
}

bool gone_within(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (alive(pid)) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

pid_t pid_in_file(const std::string& path, double seconds = 10) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    const std::string s = read_file(path);
    if (!s.empty() && s.back() == '\n') return static_cast<pid_t>(std::stol(s));
    if (std::chrono::steady_clock::now() > end) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

TEST(ChildProcess, ExitCodeIsReported) {
  ChildProcess c;
  c.spawn(shell("exit 3"));
  EXPECT_GT(c.pid(), 0);
  const auto& st = c.wait_for(10000);
  ASSERT_TRUE(st.has_value());
  EXPECT_TRUE(st->exited);
  EXPECT_EQ(st->code, 3);
  EXPECT_EQ(st->text(), "exit code 3");
  EXPECT_FALSE(c.running());
}

TEST(ChildProcess, DeathBySignalIsReportedWithItsName) {
  ChildProcess c;
  c.spawn(shell("kill -SEGV $$"));
  const auto& st = c.wait_for(10000);
  ASSERT_TRUE(st.has_value());
  EXPECT_FALSE(st->exited);
  EXPECT_EQ(st->signal, SIGSEGV);
  EXPECT_EQ(st->text(), "signal 11 (Segmentation fault)");
}

TEST(ChildProcess, PollDoesNotWaitForARunningProcess) {
  ChildProcess c;
  c.spawn(shell("sleep 30"));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(c.poll().has_value());
  EXPECT_TRUE(c.running());
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  c.terminate(1000);
  ASSERT_TRUE(c.poll().has_value());
  EXPECT_EQ(c.poll()->signal, SIGTERM);
}

TEST(ChildProcess, StdoutAndStderrGoToTheOutputFileWithArgsAndEnvironment) {
  TempDir d;
  ChildSpec s = shell("echo \"out $CHAINSIM_TEST_VALUE $0\"; echo err >&2; read x; echo \"stdin [$x]\"",
                      d.file("m.out"));
  s.args.push_back("arg0");
  s.env = {"CHAINSIM_TEST_VALUE=forty-two"};
  ChildProcess c;
  c.spawn(s);
  ASSERT_TRUE(c.wait_for(10000).has_value());
  EXPECT_EQ(c.poll()->code, 0);
  // stdin is /dev/null: read gets nothing
  EXPECT_EQ(read_file(d.file("m.out")), "out forty-two arg0\nerr\nstdin []\n");
}

// an open file of the caller's instead of a path: stdout and stderr go to it
TEST(ChildProcess, StdoutAndStderrCanGoToAnOpenFile) {
  TempDir d;
  const std::string path = d.file("out.txt");
  const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ChildProcess c;
  ChildSpec spec;
  spec.program = "/bin/sh";
  spec.args = {"-c", "echo out; echo err >&2"};
  spec.stdout_path = d.file("not-used.txt");
  spec.stdout_fd = fd;
  c.spawn(spec);
  EXPECT_TRUE(c.wait().exited);
  close(fd);
  EXPECT_EQ(read_file(path), "out\nerr\n");
  EXPECT_FALSE(fs::exists(d.file("not-used.txt")));
}

TEST(ChildProcess, ChildHasItsOwnProcessGroupAndTerminateEndsAllOfIt) {
  TempDir d;
  ChildProcess c;
  // a grandchild in the same group, its pid written for the test
  c.spawn(shell("sleep 60 & echo $! > " + d.file("grandchild") + "; wait"));
  const pid_t grandchild = pid_in_file(d.file("grandchild"));
  ASSERT_GT(grandchild, 0);
  EXPECT_EQ(getpgid(c.pid()), c.pid());       // a group of its own
  EXPECT_EQ(getpgid(grandchild), c.pid());    // which its children share
  EXPECT_NE(getpgid(c.pid()), getpgid(0));    // not ours: a terminal's Ctrl-C misses it
  c.terminate(2000);
  EXPECT_FALSE(c.running());
  EXPECT_TRUE(gone_within(grandchild, 5));
}

TEST(ChildProcess, TerminateKillsAProcessThatIgnoresSigterm) {
  TempDir d;
  ChildProcess c;
  c.spawn(shell("trap '' TERM; echo $$ > " + d.file("ready") + "; while :; do sleep 1; done"));
  ASSERT_EQ(pid_in_file(d.file("ready")), c.pid());  // the trap is set
  c.terminate(200);
  ASSERT_TRUE(c.poll().has_value());
  EXPECT_EQ(c.poll()->signal, SIGKILL);
}

TEST(ChildProcess, TerminateAllEndsEveryChild) {
  ChildProcess a, b, done;
  a.spawn(shell("sleep 60"));
  b.spawn(shell("sleep 60"));
  done.spawn(shell("exit 0"));
  done.wait_for(10000);
  terminate_all({&a, &b, &done}, 1000);
  EXPECT_FALSE(a.running());
  EXPECT_FALSE(b.running());
  EXPECT_EQ(done.poll()->code, 0);  // already ended: untouched
}

TEST(ChildProcess, ProgramThatCannotRunExitsWith127AndSaysWhy) {
  TempDir d;
  ChildSpec s;
  s.program = d.file("no-such-program");
  s.stdout_path = d.file("m.out");
  ChildProcess c;
  c.spawn(s);
  ASSERT_TRUE(c.wait_for(10000).has_value());
  EXPECT_EQ(c.poll()->code, 127);
  EXPECT_EQ(read_file(d.file("m.out")),
            "chainsim: cannot execute " + s.program + ": No such file or directory\n");
}

// PR_SET_PDEATHSIG: a server killed outright takes its modules with it
TEST(ChildProcess, ChildDiesWithItsParent) {
  TempDir d;
  const pid_t server = fork();
  ASSERT_GE(server, 0);
  if (server == 0) {
    ChildProcess c;
    c.spawn(shell("echo $$ > " + d.file("module") + "; sleep 60"));
    pid_in_file(d.file("module"));
    _exit(0);  // no destructor, no terminate: as if killed
  }
  int st = 0;
  waitpid(server, &st, 0);
  const pid_t module = pid_in_file(d.file("module"), 1);
  ASSERT_GT(module, 0);
  EXPECT_TRUE(gone_within(module, 5));
}

TEST(ChildProcess, DestructorEndsARunningChild) {
  pid_t pid = 0;
  {
    ChildProcess c;
    c.spawn(shell("sleep 60"));
    pid = c.pid();
    EXPECT_TRUE(alive(pid));
  }
  EXPECT_TRUE(gone_within(pid, 5));
}

TEST(ChildProcess, ExecutableDirIsTheDirectoryOfThisProgram) {
  EXPECT_EQ(fs::path(executable_dir()), fs::canonical("/proc/self/exe").parent_path());
}

TEST(ChildProcess, WaitGivesTheExitCodeOrTheSignal) {
  ChildProcess a;
  a.spawn(shell("exit 3"));
  const ExitStatus& s = a.wait();
  EXPECT_TRUE(s.exited);
  EXPECT_EQ(s.code, 3);
  EXPECT_EQ(s.text(), "exit code 3");
  EXPECT_FALSE(a.running());
  ChildProcess b;
  b.spawn(shell("kill -9 $$"));
  EXPECT_FALSE(b.wait().exited);
  EXPECT_EQ(b.wait().signal, 9);
  EXPECT_NE(b.wait().text().find("signal 9"), std::string::npos);
}

TEST(ChildProcess, WaitWithoutAProcessIsAnError) {
  ChildProcess a;
  EXPECT_THROW(a.wait(), std::logic_error);
}

// the first child cannot end before the test lets it (a file appears), so
// which one wait_any returns does not depend on timing
TEST(ChildProcess, WaitAnyReturnsTheOneThatEnded) {
  TempDir dir;
  const std::string gate = dir.file("gate");
  ChildProcess held, quick;
  held.spawn(shell("while [ ! -e '" + gate + "' ]; do sleep 0.01; done; exit 4"));
  quick.spawn(shell("exit 5"));
  const std::vector<ChildProcess*> both = {&held, &quick};
  EXPECT_EQ(wait_any(both), 1);
  EXPECT_EQ(quick.poll()->code, 5);
  EXPECT_TRUE(held.running());
  std::ofstream(gate) << "go";
  EXPECT_EQ(wait_any(both), 0);
  EXPECT_EQ(held.poll()->code, 4);
  EXPECT_EQ(wait_any(both), -1);  // none running
}

// the server's files (outputs, the listening socket, links) are open without
// close-on-exec here on purpose: the child must still see only 0, 1 and 2
TEST(ChildProcess, ChildInheritsOnlyStdinStdoutAndStderr) {
  TempDir dir;
  const int file = open(dir.file("trace.csv").c_str(), O_WRONLY | O_CREAT, 0644);
  const int sock = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(file, 3);
  ASSERT_GE(sock, 3);
  ChildProcess c;
  // ls runs as the shell's child and lists the shell's descriptors
  c.spawn(shell("ls /proc/$$/fd; exit 0", dir.file("out.txt")));
  ASSERT_TRUE(c.wait().exited);
  close(file);
  close(sock);
  std::istringstream in(read_file(dir.file("out.txt")));
  std::set<std::string> fds;
  for (std::string fd; in >> fd;) fds.insert(fd);
  EXPECT_EQ(fds, (std::set<std::string>{"0", "1", "2"})) << read_file(dir.file("out.txt"));
}

// a child that ends while nobody waits for it is counted by the SIGCHLD
// handler: the lockstep polls its endpoints only when the count moved
TEST(ChildProcess, ChildEndCountMovesWhenAChildEnds) {
  const unsigned before = child_end_count();
  ChildProcess c;
  c.spawn(shell("exit 0"));
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (child_end_count() == before && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_NE(child_end_count(), before);
  EXPECT_TRUE(c.poll().has_value());
}

}  // namespace
}  // namespace chainsim
