// Reliability end to end, paths: a bad --out is a bad option found before any
// module starts; nothing from a scene can name a path outside the run or
// socket directory or put control characters on the terminal; the socket
// directory of a killed server does not outlive the next run.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "scenario_util.h"

using namespace scenario;

namespace {

// `chainsim run scene --out out`, the central control a script that leaves a
// marker file: whether any module process was started
struct OutRun {
  Outcome outcome;
  bool module_started = false;
};

OutRun run_with_out(const std::string& dir, const std::string& out) {
  const std::string marker = dir + "/central-started";
  const std::string prog = write_file(dir, "central.sh", "#!/bin/sh\ntouch " + marker + "\nexit 0\n");
  chmod(prog.c_str(), 0755);
  const std::string scene = write_file(dir, "s.yaml", "chain: R\ncentral: {program: " + prog + "}\n");
  const std::string err = dir + "/stderr.txt";
  OutRun r;
  r.outcome = wait_chainsim(start_chainsim({"run", scene, "--duration", "0.2", "--out", out}, err), out, err);
  r.module_started = std::filesystem::exists(marker);
  return r;
}

}  // namespace

// each used to be exit 3 ("internal error") after the scene was loaded
TEST(ReliabilityPaths, BadOutIsExit1NamingThePathBeforeAnyModuleStarts) {
  const std::string dir = temp_dir("bad-out");
  const std::string file = write_file(dir, "a-file", "x\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {file, "exists and is not a directory"},
      {file + "/run", "cannot create the directory"},
      {"/dev/full/run", "cannot create the directory"},
      {"/proc/self/run", "cannot create the directory"},
  };
  for (const auto& [out, why] : cases) {
    const OutRun r = run_with_out(dir, out);
    EXPECT_EQ(r.outcome.signal, 0) << out;
    EXPECT_EQ(r.outcome.exit_code, 1) << out << ": " << r.outcome.stderr_text;
    EXPECT_NE(r.outcome.stderr_text.find("chainsim: --out '" + out + "': " + why), std::string::npos)
        << r.outcome.stderr_text;
    EXPECT_FALSE(r.module_started) << out;
  }
  // a file of the same name is left as it was
  EXPECT_EQ(read_file(file), "x\n");
}

// a run directory that already holds a run is said to be replaced
TEST(ReliabilityPaths, ReusedOutIsSaid) {
  const std::string dir = temp_dir("reused-out");
  const std::string out = dir + "/run";
  const OutRun first = run_with_out(dir, out);
  ASSERT_EQ(first.outcome.exit_code, 2) << first.outcome.stderr_text;  // the script never connects
  EXPECT_EQ(first.outcome.stderr_text.find("already holds a run"), std::string::npos);
  const OutRun second = run_with_out(dir, out);
  EXPECT_NE(second.outcome.stderr_text.find("--out '" + out + "' already holds a run: its files are replaced"),
            std::string::npos)
      << second.outcome.stderr_text;
}

// a server killed outright cannot remove its socket directory; the next run
// removes it (and its own at its end)
TEST(ReliabilityPaths, SocketDirectoryOfAKilledServerIsRemovedByTheNextRun) {
  const std::string dir = temp_dir("stale-socket");
  const std::string tmp = dir + "/tmp";
  std::filesystem::create_directory(tmp);
  TmpDirForChildren env(tmp);
  const std::string err = dir + "/stderr1.txt";
  const pid_t server = start_chainsim({"run", "--duration", "60", "--out", dir + "/run1"}, err);
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return (kids = children_of(server)).size() == 9; }, 30));
  ASSERT_TRUE(wait_until([&] { return read_file(dir + "/run1/trace.csv").size() > 10000; }, 60));
  const std::vector<std::string> first = socket_dirs_in(tmp);
  ASSERT_EQ(first.size(), 1u);
  ASSERT_EQ(kill(server, SIGKILL), 0);
  const Outcome killed = wait_chainsim(server, dir + "/run1", err);
  EXPECT_EQ(killed.signal, SIGKILL);
  ASSERT_TRUE(wait_until([&] {
    for (pid_t k : kids)
      if (alive(k)) return false;
    return true;
  }, 10));
  EXPECT_EQ(socket_dirs_in(tmp), first);  // left behind: nobody could remove it

  const Outcome next = run({"--duration", "0.2", "--quiet"}, dir);
  EXPECT_EQ(next.exit_code, 0) << next.stderr_text;
  EXPECT_TRUE(socket_dirs_in(tmp).empty());
}
