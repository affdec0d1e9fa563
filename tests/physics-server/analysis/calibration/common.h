// runs chainsim calibrate on one synthetic case (tests and study)
#pragma once
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "synth.h"

namespace synth {

struct Outcome {
  int exit_code = -1;
  nlohmann::json report;
};

inline Outcome calibrate_case(const Case& c, unsigned seed, const std::string& dir) {
  std::ofstream(dir + "/bench.yaml") << bench_yaml(c.truth);
  write_csv(dir + "/m.csv", generate(c.truth, seed));
  const std::string cmd = std::string("'") + CHAINSIM_EXE + "' calibrate -q --bench '" + dir +
                          "/bench.yaml' --measured '" + dir + "/m.csv' --out '" + dir + "/out' 2> '" + dir +
                          "/stderr.txt'";
  const int st = std::system(cmd.c_str());
  Outcome o;
  o.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  std::ifstream in(dir + "/out/report.json");
  if (in) o.report = nlohmann::json::parse(in, nullptr, false);
  return o;
}

inline std::string make_temp_dir() {
  char tmpl[] = "/tmp/chainsim-calib-XXXXXX";
  const char* d = mkdtemp(tmpl);
  return d ? d : "/tmp";
}

}  // namespace synth
