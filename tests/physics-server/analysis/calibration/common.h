// runs chainsim calibrate on one synthetic case (tests and study)
#pragma once
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "synth_cases.h"

namespace synth {

struct Outcome {
  int exit_code = -1;
  nlohmann::json report;
  double cpu_s = 0;   // user + system time of the calibration process
  std::vector<std::string> names;   // effects found
  std::map<std::string, std::string> variants;   // their forms
};

// runs argv with stderr to err_file; exit code and the child's CPU time (s)
inline int run_process(const std::vector<std::string>& argv, const std::string& err_file, double* cpu_s) {
  std::vector<char*> av;
  for (const std::string& a : argv) av.push_back(const_cast<char*>(a.c_str()));
  av.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 2, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, av[0], &fa, nullptr, av.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  int st = 0;
  rusage u{};
  while (wait4(pid, &st, 0, &u) < 0 && errno == EINTR) {
  }
  *cpu_s = u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// runs `exe calibrate` on dir/bench.yaml and dir/m.csv (report in dir/out)
inline Outcome calibrate_files(const std::string& dir, const std::string& exe = CHAINSIM_EXE) {
  std::filesystem::remove_all(dir + "/out");
  Outcome o;
  o.exit_code = run_process({exe, "calibrate", "-q", "--bench", dir + "/bench.yaml", "--measured",
                             dir + "/m.csv", "--out", dir + "/out"},
                            dir + "/stderr.txt", &o.cpu_s);
  std::ifstream in(dir + "/out/report.json");
  if (in) o.report = nlohmann::json::parse(in, nullptr, false);
  if (o.report.is_object())
    for (const auto& e : o.report["effects"]) {
      o.names.push_back(e["name"]);
      if (e.contains("variant")) o.variants[e["name"]] = e["variant"];
    }
  return o;
}

// `exe`: the chainsim to run (default: the one built with this test)
inline Outcome calibrate_case(const Case& c, unsigned seed, const Conditions& cond, const std::string& dir,
                              const std::string& exe = CHAINSIM_EXE) {
  const Truth t = c.truth(seed, cond);
  std::ofstream(dir + "/bench.yaml") << bench_yaml(t);
  write_csv(dir + "/m.csv", c.record(t, seed));
  return calibrate_files(dir, exe);
}

// exactly the expected effects (in any order) with the expected verdict
inline bool exactly_right(const std::vector<std::string>& expect, const std::string& verdict, const Outcome& o) {
  if (!o.report.is_object() || o.report["verdict"] != verdict) return false;
  std::vector<std::string> a = o.names, b = expect;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  return a == b;
}

inline bool exactly_right(const Case& c, const Outcome& o) { return exactly_right(c.expect, c.verdict, o); }

inline std::string make_temp_dir() {
  char tmpl[] = "/tmp/chainsim-calib-XXXXXX";
  const char* d = mkdtemp(tmpl);
  return d ? d : "/tmp";
}

}  // namespace synth
