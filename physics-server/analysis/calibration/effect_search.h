// The calibration's greedy search: while the held-out residual is structured
// (not white), fit every catalogue effect not yet in the model, rank them by
// held-out gap, and accept the best when it cuts the gap by kMinGain, lowers
// the held-out error and is not fitted to its null value.
// docs/calibration.md, "Method" 5.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "analysis/calibration/servo_fit.h"

namespace chainsim {

constexpr double kMinGain = 0.30;    // an effect must cut the held-out structured error by 30 %
constexpr double kWhiteMax = 1.6;    // whiteness ratio at or below which a residual is noise

// a progress line (the CLI prints it on stderr)
using CalibrationProgress = std::function<void(const std::string&)>;

struct Candidate {
  int effect = 0;        // catalogue index
  Fit fit;
  double signature = 0;  // regime_signature of the residual before it, in the effect's regimes
  bool accepted = false;
  std::string why;       // the decision, in words
};

struct EffectSearch {
  Fit model;                                   // the base with the accepted effects
  std::vector<std::vector<Candidate>> rounds;  // each round's candidates, best first
};

// the search from the refitted base; regime: classify_regimes of the measurement
EffectSearch search_effects(const FitProblem& p, const Fit& base, const std::vector<int>& regime,
                            const CalibrationProgress& say);

}  // namespace chainsim
