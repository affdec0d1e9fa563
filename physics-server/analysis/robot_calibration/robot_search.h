// The robot calibration's search: greedy rounds over the applicable knobs
// (each fitted onto the accepted ones; the best accepted when it cuts the
// speed gap by kMinGainRobot), at most n - 2 knobs for n rows, until the gap
// is within the table's resolution; then a leave-one-row-out check. When
// the greedy rounds leave the gap above the resolution with room for two
// knobs, pairs of knobs are fitted jointly (a pair of effects whose singles
// each fall short of the threshold); a pair is accepted only when it cuts
// the gap by the threshold, each of its knobs is needed and its
// leave-one-row-out check holds, and other pairs that fit the table as well
// are reported as aliases.
#pragma once

#include <cmath>
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

constexpr int kMaxPairFits = 3;   // pairs fitted jointly, the best singles' pairs first

// a pair of knobs fitted jointly after the greedy rounds
struct PairCandidate {
  int a = 0, b = 0;                  // knob ids, a's single fit the better
  KnobFit fit;                       // the joint fit
  double single_a = 0, single_b = 0; // each knob's gap fitted alone (from round 1)
  double leave_one_out_gap = NAN;    // NaN: not done (the pair failed before)
  std::vector<double> leave_one_out; // per row, when done
  bool acceptable = false;           // passes every check
  bool accepted = false;             // the one taken (the best acceptable)
  std::string why;
};

// two settings that the table cannot tell apart: both pass the acceptance
// checks, and their speeds differ by no more than the table's resolution
// (RMS over the rows). The accepted one is the better fit; the other is
// reported beside it, never dropped silently.
struct Alias {
  KnobSetting chosen, other;   // the accepted setting, the one it cannot be told from
  double gap_other = 0;        // the other's gap, cm/s
  double difference = 0;       // RMS of the two settings' speed difference, cm/s
};

struct RobotSearch {
  std::vector<double> before, after;   // speeds per row: nominal, with the accepted knobs
  double gap_before = 0, gap_after = 0;
  double paper_gap = 0;                // the paper's simulator's gap (NaN without its column)
  KnobSetting model;                   // the accepted knobs' factors
  std::vector<int> accepted;           // knob ids, in the order accepted
  std::vector<KnobCandidate> candidates;
  std::vector<PairCandidate> pairs;    // the pair stage (empty when it did not run)
  std::vector<Alias> aliases;          // acceptable settings the table cannot tell from an accepted one
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
