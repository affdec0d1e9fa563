#include "optimize_problems.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace optimize_test {

namespace {

const char* kBase = R"(# three rotation modules crawling in open air (the optimize tests' base scene)
name: opt-test
duration_s: 0.4
chain: RRR
central:
  params: {gait: 1, amplitude_cdeg: 3000, omega_mrad_s: 8000, phase_mrad: 1000, posture_cdeg: 5000}
output: {trace_hz: 50}
)";

const char* kGait = R"(name: test-gait
scene: base.yaml
genome:
  params:
    - {target: central.amplitude_cdeg, min: 1000, max: 5000, step: 2000}
    - {target: central.omega_mrad_s, min: 4000, max: 12000, step: 4000}
    - {target: central.phase_mrad, min: 500, max: 1500, step: 500}
measures:
  x: {kind: distance, of: chain, along: x}
  head_x: {kind: distance, of: head, along: x}
objective:
  maximize: x
ga: {population: 6, generations: 7, seed: 1}
evaluation: {trials: 1}
)";

const char* kFault = R"(name: test-fault
scene: base-fault.yaml
genome:
  params:
    - {target: "chain[1].mode", min: 0, max: 2, step: 2}   # quoted: brackets in a flow mapping
    - {target: central.amplitude_cdeg, min: 1000, max: 5000, step: 2000}
measures:
  x: {kind: distance, of: chain, along: x}
objective:
  maximize: x
  failed_fitness: -1
ga: {population: 4, generations: 2, seed: 1}
evaluation: {module_timeout_s: 5}
)";

// text with its first `from` replaced by `to`
std::string sub(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("no '" + from + "' in a test problem");
  return text.replace(at, from.size(), to);
}

}  // namespace

std::string write_problem(const std::string& dir, const std::string& which) {
  std::ofstream(dir + "/base.yaml") << kBase;
  if (which == "gait") {
    std::ofstream(dir + "/gait.yaml") << kGait;
    return dir + "/gait.yaml";
  }
  if (which == "gait-long") {  // the same search with 3 s runs: an evaluation lasts long enough to be cut
    const std::string base = sub(kBase, "duration_s: 0.4", "duration_s: 3.0");
    const std::string gait = sub(kGait, "scene: base.yaml", "scene: base-long.yaml");
    std::ofstream(dir + "/base-long.yaml") << base;
    std::ofstream(dir + "/gait-long.yaml") << gait;
    return dir + "/gait-long.yaml";
  }
  if (which == "gait-auto" || which == "gait-exact") {  // trials: auto; with the exact solver no seed matters
    std::string base = kBase, gait = sub(kGait, "evaluation: {trials: 1}\n", "");
    if (which == "gait-exact") {
      base += "physics: {solver: exact}\n";
      gait = sub(gait, "scene: base.yaml", "scene: base-exact.yaml");
    }
    std::ofstream(dir + "/base-exact.yaml") << base;
    std::ofstream(dir + "/" + which + ".yaml") << gait;
    return dir + "/" + which + ".yaml";
  }
  if (which == "stop" || which == "stop-off") {  // a constraint on when the tail gets 1 cm on
    std::string stop = sub(kGait, "  head_x: {kind: distance, of: head, along: x}\n",
                           "  t: {kind: time_to_reach, of: tail, along: x, reach_m: -0.1255}\n");
    stop = sub(stop, "objective:\n  maximize: x\n",
               "objective:\n  maximize: x\n  failed_fitness: -1\nconstraints: [{measure: t, max: 0.3}]\n");
    if (which == "stop-off") stop = sub(stop, "evaluation: {trials: 1}", "evaluation: {trials: 1, stop_on_constraints: false}");
    std::ofstream(dir + "/" + which + ".yaml") << stop;
    return dir + "/" + which + ".yaml";
  }
  if (which == "fault") {
    std::ofstream(dir + "/base-fault.yaml")
        << "name: opt-test-fault\nduration_s: 0.4\nchain:\n  - {type: rotation}\n"
           "  - {type: rotation, firmware: " FW_MISBEHAVE ", params: {mode: 0, at_ms: 150}}\n"
           "  - {type: rotation}\n"
           "central:\n  params: {gait: 1, amplitude_cdeg: 3000, omega_mrad_s: 8000, phase_mrad: 1000}\n"
           "output: {trace_hz: 50}\n";
    std::ofstream(dir + "/fault.yaml") << kFault;
    return dir + "/fault.yaml";
  }
  throw std::invalid_argument("no test problem " + which);
}

std::string history_without_wall(const std::string& path) {
  std::ifstream in(path);
  std::string line, out;
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

}  // namespace optimize_test
