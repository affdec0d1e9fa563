// Reliability end to end, the physics and the disk: a blown-up world stops the
// run with the body, module and time named (exit 4) or is warned about; a
// write that fails (disk full, a file-size limit) stops the run at once,
// naming the file (exit 5), with the trace ending on a whole row.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "scenario_util.h"

using namespace scenario;

namespace {

// a chain dropped from 10 m: in free fall it passes the 10 m/s bound at
// t = 1.01-1.02 s, long before it lands (a start inside the floor, which used to
// blow up at tens of m/s, is now refused before the run)
const char* kFallingChain =
    "chain: RRRR\n"
    "environment: {type: plane}\n"
    "placement: {position_m: [0, 0, 10]}\n";

// every line of a trace has as many fields as its header, and it ends on a newline
void expect_whole_rows(const std::string& trace) {
  ASSERT_FALSE(trace.empty());
  EXPECT_EQ(trace.back(), '\n');
  std::istringstream in(trace);
  std::string header, line;
  std::getline(in, header);
  const auto fields = [](const std::string& s) { return std::count(s.begin(), s.end(), ',') + 1; };
  int rows = 0;
  while (std::getline(in, line)) {
    ASSERT_EQ(fields(line), fields(header)) << "row " << rows;
    ++rows;
  }
}

}  // namespace

// used to be exit 0 with the chain at 70-83 m/s
TEST(ReliabilityOutput, DivergenceStopsTheRunNamingBodyModuleAndTime) {
  const std::string dir = temp_dir("diverge");
  const std::string scene = write_file(dir, "s.yaml", kFallingChain);
  const Outcome o = run({scene, "--duration", "2"}, dir);
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 4) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("physics diverged: module "), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("(rotation) body '"), std::string::npos) << o.stderr_text;
  // a free fall, which is what a chain off the end of a terrain does: said so
  EXPECT_NE(o.stderr_text.find("m/s over the bound of 10 m/s, "
                               "falling straight down (has it left the environment?) at t="),
            std::string::npos)
      << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  EXPECT_EQ(o.summary["exit_code"], 4);
  EXPECT_NE(o.summary["stopped_by"].get<std::string>().find("physics diverged"), std::string::npos);
  EXPECT_LT(o.summary["sim_time_s"].get<double>(), 1.1);
  EXPECT_GT(o.summary["sim_time_s"].get<double>(), 1.0);  // free fall: 10 m/s at 1.01-1.02 s
  expect_whole_rows(read_file(o.dir + "/trace.csv"));
  EXPECT_NE(read_file(o.dir + "/bus.log").find("fault physics diverged"), std::string::npos);
}

// a body deep inside a wall is a blow-up even while it is slow: a floor so
// soft that the chain sinks through it used to go on (exit 0)
TEST(ReliabilityOutput, DivergenceNamesABodySinkingIntoTheFloor) {
  const std::string dir = temp_dir("diverge-sink");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: sinking\nduration_s: 2\nchain: RRR\nphysics: {gravity_m_s2: 100}\n"
                                       "environment: {material: {soft_cfm: 1, soft_erp: 0}}\n");
  const Outcome o = run({scene}, dir);
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 4) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("(rotation) body '"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(" mm inside the environment or another module, over the bound of 10 mm at t="),
            std::string::npos)
      << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  EXPECT_EQ(o.summary["exit_code"], 4);
  EXPECT_LT(o.summary["sim_time_s"].get<double>(), 0.2);
  expect_whole_rows(read_file(o.dir + "/trace.csv"));
  // the same chain on the default floor in the same gravity does not sink
  const std::string firm =
      write_file(dir, "firm.yaml", "name: firm\nduration_s: 0.5\nchain: RRR\nphysics: {gravity_m_s2: 100}\n");
  EXPECT_EQ(run({firm}, dir).exit_code, 0);
}

TEST(ReliabilityOutput, DivergenceWarnGoesOnAndSaysItOnce) {
  const std::string dir = temp_dir("diverge-warn");
  const std::string scene = write_file(dir, "s.yaml", kFallingChain);
  const Outcome o = run({scene, "--duration", "1.5", "--on-divergence", "warn"}, dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  const std::string w = "chainsim: warning: physics diverged: module ";
  const size_t at = o.stderr_text.find(w);
  EXPECT_NE(at, std::string::npos) << o.stderr_text;
  EXPECT_EQ(o.stderr_text.find(w, at + 1), std::string::npos) << o.stderr_text;
  EXPECT_NEAR(o.summary["sim_time_s"].get<double>(), 1.5, 1e-9);
}

// a chain started 4 cm inside the floor is refused before anything runs,
// naming the deepest body (it used to be thrown out at 20 m/s at the first step)
TEST(ReliabilityOutput, AStartInsideTheEnvironmentIsRefusedNamingTheBody) {
  const std::string dir = temp_dir("buried");
  const std::string scene = write_file(dir, "s.yaml",
                                       "chain: RRRR\n"
                                       "environment: {type: plane}\n"
                                       "placement: {position_m: [0, 0, -0.04]}\n");
  const Outcome o = run({scene, "--duration", "1"}, dir);
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 1) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("(rotation) body '"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("mm inside the environment"), std::string::npos) << o.stderr_text;
  EXPECT_FALSE(std::filesystem::exists(o.dir + "/trace.csv")) << "nothing ran";
}

// a shipped-like scene does not come near the bounds
TEST(ReliabilityOutput, OrdinaryRunDoesNotDiverge) {
  const Outcome o = run({"--duration", "1", "--quiet"}, temp_dir("no-diverge"));
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
}

// trace.csv a link to /dev/full: every write to it fails with ENOSPC
TEST(ReliabilityOutput, DiskFullStopsTheRunNamingTheFile) {
  const std::string dir = temp_dir("disk-full");
  const std::string out = dir + "/run";
  std::filesystem::create_directories(out);
  std::filesystem::create_symlink("/dev/full", out + "/trace.csv");
  const std::string err = dir + "/stderr.txt";
  const Outcome o = wait_chainsim(start_chainsim({"run", "--duration", "20", "--out", out}, err), out, err);
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 5) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("cannot write " + out + "/trace.csv: No space left on device at t="),
            std::string::npos)
      << o.stderr_text;
  // at once: the first 64 KiB buffer, not at the end of the 20 s
  ASSERT_TRUE(o.summary.is_object()) << o.stderr_text;
  EXPECT_LT(o.summary["sim_time_s"].get<double>(), 10.0);
  EXPECT_EQ(o.summary["exit_code"], 5);
  EXPECT_FALSE(std::filesystem::exists(out + "/summary.json.tmp"));
}

// a file-size limit (RLIMIT_FSIZE, as ulimit -f) cuts the trace mid-row: it is
// cut back to its last whole row, and what was written is kept
TEST(ReliabilityOutput, TraceCutByAFileSizeLimitEndsOnAWholeRow) {
  const std::string dir = temp_dir("fsize");
  const std::string out = dir + "/run";
  const std::string err = dir + "/stderr.txt";
  // 200 blocks of 512 bytes (POSIX sh), more than summary.json, less than the trace
  const std::string cmd = std::string("ulimit -f 200 && exec ") + CHAINSIM_EXE + " run --duration 20 --out " + out;
  const pid_t pid = fork();
  if (pid == 0) {
    freopen(err.c_str(), "w", stderr);
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const Outcome o = wait_chainsim(pid, out, err);
  EXPECT_EQ(o.signal, 0) << o.stderr_text;
  EXPECT_EQ(o.exit_code, 5) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("cannot write " + out + "/trace.csv: File too large"), std::string::npos)
      << o.stderr_text;
  const std::string trace = read_file(out + "/trace.csv");
  EXPECT_GT(trace.size(), 50000u);
  EXPECT_LE(trace.size(), 200u * 512u);
  expect_whole_rows(trace);
  // the summary's hash is the hash of the file as it stays
  ASSERT_TRUE(o.summary.is_object());
  EXPECT_EQ(o.summary["trace_sha256"], sha256_file(out + "/trace.csv"));
}
