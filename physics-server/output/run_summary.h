// summary.json of a run directory: what ran, how long, how it ended, each
// endpoint's process and fault, the chain's displacement (README.md's table
// of the run directory lists the keys).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace chainsim {

// one endpoint (a module, or the central control) as the run ended
struct EndpointSummary {
  int index = 0;
  std::string type;                 // module type, or "central"
  std::string program;
  uint32_t pid = 0;
  std::string fault;                // empty: none
  uint64_t exchanges = 0;           // TickBegin/TickEnd round trips
  std::optional<double> energy_j;   // modules: supply energy over the run
  uint8_t i2c_address = 0;          // at the end (a module: the one discovery gave it); 0: none
  int64_t addressed_us = -1;        // when it took that address
  std::string target = "native";    // or "pic"
  // pic: what chainsim-pic measured (cycles per step against the period,
  // stack high-water marks, flash and RAM), or {"error": why} when it left none
  nlohmann::json pic;
};

struct RunSummary {
  int64_t sim_time_us = 0;          // where the run (and its trace) ended
  double wall_time_s = 0;
  bool limp_mode = false;           // --on-module-fault=limp
  std::string trace_sha256;
  uint64_t exchanges = 0;
  int64_t degenerate_lcp_steps = 0; // World::degenerate_lcp_steps (the exact solver)
  std::vector<EndpointSummary> endpoints;
  Eigen::Vector3d displacement_m = Eigen::Vector3d::Zero();  // of the chain's centre of mass
  // discovery, judged at discovery_us when the run got that far: the modules
  // with no I2C address then, failed (silent) and allowed to (allowed_silent)
  int64_t discovery_us = 0;
  bool discovery_judged = false;
  std::vector<int> silent, allowed_silent;
  int exit_code = 0;
  std::string stopped_by;           // empty: it ran to the end
  std::string early_stop;           // a stop_when rule ended it (finished, exit code 0): what it saw
};

nlohmann::json summary_json(const Scene& scene, const RunSummary& run);

}  // namespace chainsim
