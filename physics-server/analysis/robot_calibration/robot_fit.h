// The robot calibration's fits: knob factors that bring the simulated speeds
// to the measured ones (RMS over the table's rows). One knob: a log grid,
// then golden-section refinement; several: NLopt BOBYQA on the log factors.
// The speeds come from a function (scene runs, or anything in a test).
#pragma once

#include <functional>
#include <vector>

#include "analysis/robot_calibration/robot_knobs.h"
#include "analysis/robot_calibration/speed_table.h"

namespace chainsim {

// simulated speed per row, cm/s, for a setting
using SpeedFunction = std::function<std::vector<double>(const KnobSetting&)>;

// RMS over the rows in mask (all when empty) of simulated - real, cm/s
double speed_gap(const std::vector<double>& sim, const std::vector<SpeedRow>& rows,
                 const std::vector<bool>& mask = {});

struct KnobFit {
  KnobSetting st;
  double gap = 0;   // speed_gap at st
  int evals = 0;    // settings asked for
};

// knob k alone, the others held at `fixed`: a log grid of 7 over its range,
// then 6 golden-section steps around the best
KnobFit fit_one_knob(const SpeedFunction& speeds, const std::vector<SpeedRow>& rows, const KnobSetting& fixed,
                     int k, const std::vector<bool>& mask);

// every knob of `start` together, from start; never worse than start
KnobFit fit_knobs(const SpeedFunction& speeds, const std::vector<SpeedRow>& rows, const KnobSetting& start,
                  const std::vector<bool>& mask, int max_eval = 30);

// a new knob onto st0: alone first, then all jointly (alone when st0 is empty)
KnobFit fit_new_knob(const SpeedFunction& speeds, const std::vector<SpeedRow>& rows, const KnobSetting& st0,
                     int new_knob, const std::vector<bool>& mask);

}  // namespace chainsim
