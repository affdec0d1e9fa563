// The fault-injection suite, a kill storm: runs of the default scene (eight
// modules and the central control), each with one process of its tree killed
// at a random wall time, the process and the signal picked by a seeded
// generator. Each run must end as docs/reliability.md says: a module or the
// central control killed is exit 2, named with its pid and signal on stderr,
// in summary.json and in bus.log; the server interrupted (SIGTERM, SIGINT) is
// exit 130 with its outputs whole; the server killed outright leaves no
// process behind and its socket directory goes with the next run. No process
// of any run outlives it, summary.json parses, trace.csv ends on a whole row.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

#include "input_mutator.h"  // SplitMix
#include "scenario_util.h"

using namespace scenario;

namespace {

constexpr int kRuns = 20;
constexpr uint64_t kSeed = 16;
constexpr int kMaxDelayMs = 1200;  // after the first module process exists

// the value of NAME= in a process's environment, empty when absent
std::string env_of(pid_t pid, const std::string& name) {
  const std::string env = read_file("/proc/" + std::to_string(pid) + "/environ");
  const std::string key = name + "=";
  for (size_t b = 0; b < env.size();) {
    const size_t e = env.find('\0', b);
    const std::string item = env.substr(b, e - b);
    if (item.rfind(key, 0) == 0) return item.substr(key.size());
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return "";
}

// trace.csv's rows each have the header's columns, all numbers, the last
// one ended too (even when the server was killed outright)
std::string trace_problem(const std::string& path) {
  const std::string text = read_file(path);
  if (text.empty()) return "";  // killed before the first flush
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  const size_t columns = static_cast<size_t>(std::count(line.begin(), line.end(), ',')) + 1;
  if (text.back() != '\n') return "the last row is torn";
  size_t row = 0;
  while (std::getline(in, line)) {
    ++row;
    std::stringstream r(line);
    size_t n = 0;
    for (std::string v; std::getline(r, v, ','); ++n) {
      char* end = nullptr;
      std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0') return "row " + std::to_string(row) + ": '" + v + "' is not a number";
    }
    if (n != columns)
      return "row " + std::to_string(row) + " has " + std::to_string(n) + " columns of " + std::to_string(columns);
  }
  return "";
}

struct Tally {
  std::map<std::string, int> victims;  // "server SIGKILL", "module SIGSEGV", ...
  std::map<int, int> exits;            // exit code, or -signal
  int orphaned_runs = 0, bad_traces = 0;
};

}  // namespace

TEST(FaultInjection, KillStormEndsEveryRunAsDocumented) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string work = temp_dir("kill-storm");
  const std::string tmp = work + "/tmp";
  std::filesystem::create_directory(tmp);
  TmpDirForChildren env(tmp);
  SplitMix r(kSeed);
  Tally t;
  bool last_left_a_socket_dir = false;
  for (int run = 0; run < kRuns; ++run) {
    const std::string dir = work + "/run" + std::to_string(run);
    const std::string err = work + "/stderr" + std::to_string(run) + ".txt";
    const pid_t server = start_chainsim({"run", "--duration", "60", "-q", "--out", dir}, err);
    ASSERT_TRUE(wait_until([&] { return !children_of(server).empty(); }, 30)) << "run " << run;
    std::this_thread::sleep_for(std::chrono::milliseconds(r.below(kMaxDelayMs + 1)));

    // the victim: the server a quarter of the time, the central control a
    // quarter, a module half (whichever exist at that moment)
    const std::vector<pid_t> tree = children_of(server);
    std::vector<pid_t> modules, central;
    for (pid_t p : tree) {
      const std::string type = env_of(p, "CHAINSIM_MODULE_TYPE");  // empty before its exec: not a candidate
      if (!type.empty()) (type == "central" ? central : modules).push_back(p);
    }
    const size_t pick = r.below(4);
    pid_t victim = server;
    if (pick == 1 && !central.empty()) victim = central[0];
    if (pick >= 2 && !modules.empty()) victim = modules[r.below(modules.size())];
    static const int kServerSignals[] = {SIGKILL, SIGTERM, SIGINT};
    static const int kModuleSignals[] = {SIGKILL, SIGTERM, SIGSEGV, SIGABRT};
    const int sig = victim == server ? kServerSignals[r.below(3)] : kModuleSignals[r.below(4)];
    const std::string index = victim == server ? "" : env_of(victim, "CHAINSIM_MODULE_INDEX");
    const std::string type = victim == server ? "server" : env_of(victim, "CHAINSIM_MODULE_TYPE");
    ASSERT_TRUE(victim == server || !index.empty()) << "run " << run << ": pid " << victim << " is gone already";
    ASSERT_EQ(kill(victim, sig), 0);
    const Outcome o = wait_chainsim(server, dir, err, 120);
    const std::string about = "run " + std::to_string(run) + ": " + strsignal(sig) + " to " + type +
                              (index.empty() ? "" : " " + index) + " (pid " + std::to_string(victim) + ")";
    ++t.victims[(type == "server" || type == "central" ? type : "module") + " " + sigabbrev_np(sig)];
    ++t.exits[o.signal ? -o.signal : o.exit_code];
    std::printf("  %s: %s\n", about.c_str(),
                o.signal ? ("killed by " + std::string(strsignal(o.signal))).c_str()
                         : ("exit " + std::to_string(o.exit_code)).c_str());

    // nothing outlives the run: the processes seen, and any whose environment names its socket
    const std::string its_socket = "CHAINSIM_SOCKET=" + tmp + "/chainsim-sock-" + std::to_string(server) + "-";
    const bool none_left = wait_until([&] {
      for (pid_t p : tree)
        if (alive(p)) return false;
      return processes_with_env(its_socket).empty();
    }, 10);
    EXPECT_TRUE(none_left) << about << ": orphans";
    t.orphaned_runs += !none_left;

    const bool server_killed = victim == server && sig == SIGKILL;
    const std::string trace = trace_problem(dir + "/trace.csv");
    EXPECT_EQ(trace, "") << about;
    t.bad_traces += !trace.empty();
    if (server_killed) {
      EXPECT_EQ(o.signal, SIGKILL) << about;
      EXPECT_TRUE(o.summary.is_null()) << about;  // it could write nothing more
      last_left_a_socket_dir = true;
      continue;
    }
    // the run removed its own socket directory and any a killed server left
    EXPECT_TRUE(socket_dirs_in(tmp).empty()) << about;
    last_left_a_socket_dir = false;
    ASSERT_TRUE(o.summary.is_object()) << about << ": summary.json missing or not JSON\n" << o.stderr_text;
    EXPECT_EQ(o.summary["exit_code"], o.exit_code) << about;
    if (victim == server) {
      EXPECT_EQ(o.exit_code, 130) << about << "\n" << o.stderr_text;
      const std::string by = "interrupted by " + std::string(strsignal(sig));
      EXPECT_EQ(o.summary["stopped_by"].get<std::string>().rfind(by, 0), 0u) << about << o.summary["stopped_by"];
      EXPECT_NE(o.stderr_text.find("chainsim: run stopped: " + by), std::string::npos) << about << o.stderr_text;
      continue;
    }
    EXPECT_EQ(o.exit_code, 2) << about << "\n" << o.stderr_text;
    const int i = std::stoi(index);
    const auto& fault = o.summary["modules"][i]["fault"];
    ASSERT_TRUE(fault.is_string()) << about << "\n" << o.summary.dump(2);
    const std::string f = fault.get<std::string>();
    const std::string who = (type == "central" ? "central control" : "module " + index) + " (" + type + ", pid " +
                            std::to_string(victim) + ")";
    EXPECT_EQ(f.rfind(who, 0), 0u) << about << ": " << f;
    EXPECT_NE(f.find("signal " + std::to_string(sig) + " ("), std::string::npos) << about << ": " << f;
    EXPECT_EQ(o.summary["stopped_by"], fault) << about;
    EXPECT_NE(o.stderr_text.find("chainsim: run stopped: " + f), std::string::npos) << about << o.stderr_text;
    EXPECT_NE(read_file(dir + "/bus.log").find("fault " + f), std::string::npos) << about;
    // every other endpoint is healthy in the summary: one fault, the victim's
    for (size_t k = 0; k < o.summary["modules"].size(); ++k)
      if (static_cast<int>(k) != i) {
        EXPECT_TRUE(o.summary["modules"][k]["fault"].is_null()) << about << " " << k;
      }
  }
  // a server killed in the last run left its directory; a run removes it
  if (last_left_a_socket_dir) {
    const Outcome after = run({"--duration", "0.01", "-q"}, work);
    EXPECT_EQ(after.exit_code, 0) << after.stderr_text;
    EXPECT_TRUE(socket_dirs_in(tmp).empty());
  }

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("kill storm: %d runs (seed %llu), a process killed in each at 0-%.1f s after the modules started\n",
              kRuns, static_cast<unsigned long long>(kSeed), kMaxDelayMs / 1000.0);
  std::printf("  killed:");
  for (const auto& [what, n] : t.victims) std::printf(" %s %d,", what.c_str(), n);
  std::printf("\n  ended:");
  for (const auto& [code, n] : t.exits)
    std::printf(code < 0 ? " signal %d: %d," : " exit %d: %d,", code < 0 ? -code : code, n);
  std::printf("\n  runs with a process left behind: %d; traces not of whole rows: %d; wall time %.1f s\n",
              t.orphaned_runs, t.bad_traces, wall);
}
