// Where a calibration residual lives: every sample of a measurement gets a
// regime (step onset, reversal, high current, braking, slewing, hold) from
// the measurement alone; contiguous runs of one regime are the report's
// regions; an effect's signature is how much the residual concentrates in the
// regimes it acts in. docs/calibration.md, "Method" 3.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "analysis/calibration/measured_record.h"
#include "analysis/calibration/residual_stats.h"

namespace chainsim {

// regime names, by index
const std::vector<std::string>& regime_names();
enum Regime { kStepOnset = 0, kReversal, kHighCurrent, kBraking, kSlewing, kHold };

// the regime of every sample: 40 ms after a set-point change of > 0.25 deg:
// step onset, or reversal when it changes direction; else current above
// 60 % of stall_current_a: high current; else moving faster than 20 deg/s
// (over +-5 ms): braking within 20 deg of the set-point, slewing farther
// out; else hold
std::vector<int> classify_regimes(const MeasuredRecord& m, double stall_current_a);

// share of the residual energy in these regimes over their share of time
// (> 1: the residual concentrates there); 0 when there is none
double regime_signature(const Residual& r, const std::vector<int>& regime, const std::vector<std::string>& names);

// a contiguous run of one regime, samples first..last
struct RegimeRun {
  size_t first = 0, last = 0;
  int regime = 0;
};
std::vector<RegimeRun> regime_runs(const std::vector<int>& regime);

}  // namespace chainsim
