// Helpers of the scenario tests: start build/bin/chainsim as a real process,
// find its module processes, read what it wrote.
#pragma once

#include <sys/types.h>

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace scenario {

struct Outcome {
  int exit_code = -1;       // -1 when killed by a signal
  int signal = 0;
  std::string stderr_text;
  std::string dir;          // the run directory
  nlohmann::json summary;   // summary.json, null when missing
};

// a fresh directory under /tmp for one test
std::string temp_dir(const std::string& tag);
// write text to dir/name; returns the path
std::string write_file(const std::string& dir, const std::string& name, const std::string& text);
std::string read_file(const std::string& path);

// start `chainsim args...` with stderr to err_path
pid_t start_chainsim(const std::vector<std::string>& args, const std::string& err_path);
// wait for it (killing it after timeout_s) and collect the outcome
Outcome wait_chainsim(pid_t pid, const std::string& out_dir, const std::string& err_path, double timeout_s = 240);
// `chainsim <args>` (a shell command line) run to its end: stdout and
// stderr together, and the exit code (-1 if it did not exit)
std::pair<std::string, int> chainsim_stdout(const std::string& args);
// both at once: `chainsim run <args> --out <dir>/run`
Outcome run(const std::vector<std::string>& args, const std::string& dir);

// direct children of pid, from /proc
std::vector<pid_t> children_of(pid_t pid);
bool alive(pid_t pid);
// poll pred every 10 ms until true or timeout_s; returns its last value
bool wait_until(const std::function<bool()>& pred, double timeout_s);

std::string sha256_file(const std::string& path);

// trace.csv as column name -> values
std::map<std::string, std::vector<double>> read_trace(const std::string& path);
// scenes/<name>.yaml of the repository
std::string scene_path(const std::string& name);
// run scenes/<name>.yaml (name may hold a folder: optimize/x) for
// duration_s (quiet), after replacing each edits[i].first in its text by
// .second (a missing one fails the test); tag names the test's /tmp directory
Outcome run_scene(const std::string& tag, const std::string& name, double duration_s,
                  const std::vector<std::pair<std::string, std::string>>& edits = {});
// run_scene's edit that makes a scene step with the exact solver (scenes
// whose physics set tick_us: 1000, e.g. the elbow scenes)
inline const std::pair<std::string, std::string> kExactSolver = {"tick_us: 1000", "tick_us: 1000\n  solver: exact"};
// the central control's log of a run of n modules (it is endpoint n)
std::string central_log(const Outcome& o, int n);
// the times (s) of a program's log lines "<what> at ms N" (e.g. "elbow:
// bend"), in the log's order
std::vector<double> log_times(const std::string& log, const std::string& what);

// an environment variable for the processes a test starts (value nullptr:
// unset), restored when it goes
struct EnvForChildren {
  std::string name, old;
  bool had = false;
  EnvForChildren(const std::string& name, const char* value);
  ~EnvForChildren();
  EnvForChildren(const EnvForChildren&) = delete;
  EnvForChildren& operator=(const EnvForChildren&) = delete;
};

// TMPDIR for the chainsim processes a test starts (their socket directories)
struct TmpDirForChildren : EnvForChildren {
  explicit TmpDirForChildren(const std::string& dir) : EnvForChildren("TMPDIR", dir.c_str()) {}
};

// the socket directories in dir (chainsim-sock-*)
std::vector<std::string> socket_dirs_in(const std::string& dir);

// the processes whose environment holds `text` (e.g. a run's CHAINSIM_SOCKET)
std::vector<pid_t> processes_with_env(const std::string& text);

}  // namespace scenario
