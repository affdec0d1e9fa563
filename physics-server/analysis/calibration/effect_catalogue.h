// The calibration's catalogue: the base parameters it refits (as factors of
// the datasheet) and the effects of the servo model it may add (ServoParams
// members, off at 0; servo_model.h). An effect whose physics has two forms
// has one entry per form (its variant); the search names the one that fits.
// docs/calibration.md.
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

struct EffectParam {
  const char* name;        // its name in report.json
  double ServoParams::*member;
  double to_model;         // model value = param value * to_model
  double lo, hi;           // fit bounds (param units)
  bool log_scale = false;  // fitted on log(value) (lo > 0)
};

// how an effect's parameters are fitted
enum class EffectFit {
  smooth,       // with the base, by the bounded least squares (servo_fit.h)
  frame_clock,  // period and phase from the set-point changes' delays (frame_clock.h), then held
};

struct Effect {
  const char* name;        // the effect, as reported
  const char* variant;     // its form ("" when it has one)
  const char* form;        // the form in words (report)
  std::vector<EffectParam> params;            // params[0] = its size: 0 (or its bound) removes it
  std::vector<std::vector<double>> starts;    // parameter vectors tried as starts
  std::vector<std::string> regimes;           // where it acts (regimes.h)
  EffectFit fit = EffectFit::smooth;
  // the simpler form of the same effect that this one refines (one more
  // parameter); "" for none, and a form that refines nothing itself. A
  // refining form is fitted only in a round where its simpler form shows the
  // effect, or (a frame clock) finds no clock (effect_search.h)
  const char* refines = "";
};

const std::vector<Effect>& effect_catalogue();

// the catalogue entries of one effect (its variants), by name
std::vector<int> effect_variants(const std::string& name);

// x = the base factors (kNumBase), then the parameters of each effect in
// `effects` (catalogue indices), in order
size_t param_count(const std::vector<int>& effects);
size_t param_offset(const std::vector<int>& effects, size_t e);   // of effects[e]'s first

// the datasheet with x applied
BenchConfig model_config(const BenchConfig& datasheet, const std::vector<int>& effects,
                         const std::vector<double>& x);

// the fitted base values of a config, in kBaseNames' order (Kp, Kt, R, load)
std::vector<double> base_values(const BenchConfig& b);

}  // namespace chainsim
