// The evidence for each accepted effect, where it acts (reversals, holds,
// frame edges, high-current moves): the windows of its regimes where the
// model without it (the round's reference) missed the measurement most
// against the final model, plotted measured vs model before and after.
// docs/calibration.md, "Report".
#pragma once

#include <string>
#include <vector>

#include "analysis/calibration/servo_calibration.h"

namespace chainsim {

struct EvidenceWindow {
  size_t first = 0, last = 0;   // samples
  std::string regime;
  double error_before = 0, error_after = 0;   // rms normalised residual in the window
};

struct EffectEvidence {
  size_t index = 0;     // in the final model's effects
  std::string where;    // "reversals", "holds", ...
  std::vector<EvidenceWindow> windows;   // at most 3, largest improvement first
};

// per accepted effect
std::vector<EffectEvidence> effect_evidence(const ServoCalibration& c);

// its windows as a grid of panels: angle (and current) in each
std::string evidence_svg(const ServoCalibration& c, const EffectEvidence& e);

}  // namespace chainsim
