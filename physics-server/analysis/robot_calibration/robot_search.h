// The robot calibration's search: greedy rounds over the applicable knobs
// (each fitted onto the accepted ones; the best accepted when it cuts the
// speed gap by kMinGainRobot), at most n - 2 knobs for n rows, until the gap
// is within the table's resolution; then a leave-one-row-out check.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "analysis/robot_calibration/robot_fit.h"

namespace chainsim {

constexpr double kMinGainRobot = 0.30;     // a knob must cut the RMS gap by 30 %
constexpr double kTableResolution = 0.05;  // cm/s: the tables give 0.1 cm/s, so +-0.05 is rounding

struct KnobCandidate {
  int round = 0;
  int knob = 0;
  KnobFit fit;
  bool accepted = false;
  std::string why;   // the decision, in words
};

struct RobotSearch {
  std::vector<double> before, after;   // speeds per row: nominal, with the accepted knobs
  double gap_before = 0, gap_after = 0;
  double paper_gap = 0;                // the paper's simulator's gap (NaN without its column)
  KnobSetting model;                   // the accepted knobs' factors
  std::vector<int> accepted;           // knob ids, in the order accepted
  std::vector<KnobCandidate> candidates;
  std::vector<double> leave_one_out;   // per row: predicted with the knobs refitted without it (NaN: not done)
  double leave_one_out_gap = 0;        // NaN when not done
  std::string verdict;                 // explained, no_missing_effect or unexplained
};

// progress lines
using RobotProgress = std::function<void(const std::string&)>;

RobotSearch search_knobs(const std::vector<SpeedRow>& rows, const std::vector<int>& usable,
                         const SpeedFunction& speeds, const RobotProgress& say);

// printf "%.*f"; |v| < 1e-12 prints as 0
std::string fmt_fixed(double v, int prec = 3);

}  // namespace chainsim
