// The calibration's catalogue: the base parameters it refits (as factors of
// the datasheet) and the effects of the servo model it may add (each a
// ServoParams member, off at 0; servo_model.h). docs/calibration.md.
#pragma once

#include <string>
#include <vector>

#include "analysis/servo_bench/bench_config.h"

namespace chainsim {

// base factors: Kp, Km = Kt (one factor), R, load inertia
constexpr int kNumBase = 4;
extern const char* const kBaseNames[kNumBase];   // their names in report.json
// bounds of a base factor
constexpr double kBaseFactorLo = 0.6, kBaseFactorHi = 1.6;

struct Effect {
  const char* name;
  const char* param;       // its name in report.json
  double ServoParams::*member;
  double to_model;         // model value = param value * to_model
  double lo, hi;           // fit bounds (param units)
  std::vector<double> grid;
  std::vector<std::string> regimes;  // where its signature is expected (regimes.h)
  bool discrete = false;   // chosen from the grid only (not refined continuously)
};

const std::vector<Effect>& effect_catalogue();

// the datasheet with x applied: x = the base factors (kNumBase), then one
// parameter value per effect in `effects` (indices into the catalogue)
BenchConfig model_config(const BenchConfig& datasheet, const std::vector<int>& effects,
                         const std::vector<double>& x);

// the fitted base values of a config, in kBaseNames' order (Kp, Kt, R, load)
std::vector<double> base_values(const BenchConfig& b);

}  // namespace chainsim
