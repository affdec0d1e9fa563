// The robot calibration's search (robot_search.h).
#include "analysis/robot_calibration/robot_search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace chainsim {
namespace {

// one round: every usable knob not yet in cur, fitted onto it; best first
std::vector<KnobCandidate> fit_round(int round, const std::vector<SpeedRow>& rows, const std::vector<int>& usable,
                                     const SpeedFunction& speeds, const KnobSetting& cur, const RobotProgress& say) {
  std::vector<KnobCandidate> cands;
  for (int k : usable) {
    if (cur.count(k)) continue;
    KnobCandidate c;
    c.round = round;
    c.knob = k;
    c.fit = fit_new_knob(speeds, rows, cur, k, {});
    say("round " + std::to_string(round) + ": " + robot_knobs()[k].name + " -> gap " + fmt_fixed(c.fit.gap));
    cands.push_back(c);
  }
  std::sort(cands.begin(), cands.end(),
            [](const KnobCandidate& x, const KnobCandidate& y) { return x.fit.gap < y.fit.gap; });
  return cands;
}

// the accepted knobs refitted without row i, then row i predicted
double predict_left_out(const std::vector<SpeedRow>& rows, const std::vector<int>& accepted,
                        const SpeedFunction& speeds, size_t i) {
  std::vector<bool> mask(rows.size(), true);
  mask[i] = false;
  KnobSetting st;
  for (int k : accepted) st = fit_new_knob(speeds, rows, st, k, mask).st;
  return speeds(st)[i];
}

}  // namespace

std::string fmt_fixed(double v, int prec) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", prec, std::fabs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

RobotSearch search_knobs(const std::vector<SpeedRow>& rows, const std::vector<int>& usable,
                         const SpeedFunction& speeds, const RobotProgress& say) {
  const size_t n = rows.size();
  RobotSearch s;
  s.before = speeds({});
  s.gap_before = speed_gap(s.before, rows);
  s.paper_gap = NAN;
  {
    bool all = true;
    double sum = 0;
    for (const auto& row : rows) all = all && std::isfinite(row.paper), sum += std::pow(row.paper - row.real, 2);
    if (all) s.paper_gap = std::sqrt(sum / n);
  }
  say("gap before " + fmt_fixed(s.gap_before) + " cm/s RMS (paper's simulator: " + fmt_fixed(s.paper_gap) + ")");

  s.gap_after = s.gap_before;
  // at most n - 2 parameters, so that the fit keeps two degrees of freedom
  const size_t max_params = std::min<size_t>(2, n >= 3 ? n - 2 : 0);
  for (int round = 1; s.accepted.size() < max_params && s.gap_after > kTableResolution; ++round) {
    std::vector<KnobCandidate> cands = fit_round(round, rows, usable, speeds, s.model, say);
    if (cands.empty()) break;
    bool took = false;
    for (size_t i = 0; i < cands.size(); ++i) {
      KnobCandidate& c = cands[i];
      const Knob& kb = robot_knobs()[c.knob];
      const double fac = c.fit.st.at(c.knob);
      const bool at_null = std::fabs(std::log(fac)) < 0.01;
      const bool at_bound = fac <= kb.lo * 1.01 || fac >= kb.hi / 1.01;
      if (i > 0) c.why = "not the best of the round";
      else if (at_null) c.why = "fitted to its nominal value";
      else if (c.fit.gap > (1 - kMinGainRobot) * s.gap_after)
        c.why = "cuts the gap by " + fmt_fixed(100 * (1 - c.fit.gap / s.gap_after), 0) + " % (< " +
                fmt_fixed(100 * kMinGainRobot, 0) + " %)";
      else c.accepted = true, c.why = "accepted";
      if (c.accepted && at_bound) c.why += " (at a bound of its range)";
      if (c.accepted) s.model = c.fit.st, s.gap_after = c.fit.gap, s.accepted.push_back(c.knob), took = true;
      s.candidates.push_back(c);
    }
    if (!took) break;
  }
  s.after = speeds(s.model);

  s.leave_one_out.assign(n, NAN);
  s.leave_one_out_gap = NAN;
  if (!s.accepted.empty() && n >= 3) {
    say("leave-one-row-out check");
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
      s.leave_one_out[i] = predict_left_out(rows, s.accepted, speeds, i);
      sum += std::pow(s.leave_one_out[i] - rows[i].real, 2);
    }
    s.leave_one_out_gap = std::sqrt(sum / n);
  }
  const bool explained = s.gap_after <= kTableResolution;
  s.verdict = s.accepted.empty() ? (explained ? "no_missing_effect" : "unexplained")
                                 : (explained ? "explained" : "unexplained");
  return s;
}

}  // namespace chainsim
