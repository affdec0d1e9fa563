// The servo test stand's configuration: the servo's parameters, the load it
// turns and the physics step, read from a bench file (YAML;
// docs/servo-bench.md).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "model/servo_params.h"

namespace chainsim {

struct BenchConfig {
  ServoParams servo;                 // Table 1 defaults
  double load_inertia_kgm2 = 3.0e-6;
  double load_torque_nm = 0.0;
  int64_t dt_us = 500;
};

// a bench file error, "file:line:column: what"
struct BenchError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// reads a bench file (every key optional; an empty file is all defaults);
// throws BenchError
BenchConfig load_bench_config(const std::string& file);
// the same from text; `file` is used in messages
BenchConfig load_bench_text(const std::string& text, const std::string& file);

}  // namespace chainsim
