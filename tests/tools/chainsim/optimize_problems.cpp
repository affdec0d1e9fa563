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

}  // namespace

std::string write_problem(const std::string& dir, const std::string& which) {
  std::ofstream(dir + "/base.yaml") << kBase;
  if (which == "gait") {
    std::ofstream(dir + "/gait.yaml") << kGait;
    return dir + "/gait.yaml";
  }
  if (which == "gait-long") {  // the same search with 3 s runs: an evaluation lasts long enough to be cut
    std::string base = kBase, gait = kGait;
    base.replace(base.find("duration_s: 0.4"), 15, "duration_s: 3.0");
    gait.replace(gait.find("scene: base.yaml"), 16, "scene: base-long.yaml");
    std::ofstream(dir + "/base-long.yaml") << base;
    std::ofstream(dir + "/gait-long.yaml") << gait;
    return dir + "/gait-long.yaml";
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
