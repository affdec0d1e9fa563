// The robot calibration's search (robot_search.h).
#include "analysis/robot_calibration/robot_search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

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

// each row predicted by the setting refit(mask) finds with that row masked out
std::vector<double> leave_each_row_out(size_t n, const SpeedFunction& speeds,
                                       const std::function<KnobSetting(const std::vector<bool>&)>& refit) {
  std::vector<double> out(n);
  for (size_t i = 0; i < n; ++i) {
    std::vector<bool> mask(n, true);
    mask[i] = false;
    out[i] = speeds(refit(mask))[i];
  }
  return out;
}

double rms_difference(const std::vector<double>& x, const std::vector<double>& y) {
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += (x[i] - y[i]) * (x[i] - y[i]);
  return x.empty() ? 0 : std::sqrt(s / double(x.size()));
}

std::string percent_cut(double from, double to) { return fmt_fixed(100 * (1 - to / from), 0) + " %"; }

// a cut from `from` to `to` short of kMinGainRobot, in words
std::string short_cut(double from, double to) {
  return "cuts the gap by " + percent_cut(from, to) + " (< " + fmt_fixed(100 * kMinGainRobot, 0) + " %)";
}

std::string pair_name(int a, int b) { return std::string(robot_knobs()[a].name) + " + " + robot_knobs()[b].name; }

// records `other` as an alias of `chosen` when it predicts the table within
// its resolution of it (RMS over the rows); its reason then says so
void note_alias(RobotSearch& s, const KnobSetting& chosen, const KnobFit& other, const SpeedFunction& speeds,
                const std::string& of_what, std::string* why) {
  const double d = rms_difference(speeds(chosen), speeds(other.st));
  if (d > kTableResolution) return;
  s.aliases.push_back({chosen, other.st, other.gap, d});
  *why = "an alias of the accepted " + of_what + ": the table cannot tell them apart (speeds within " + fmt_fixed(d) +
         " cm/s RMS)";
}

// The pair stage: pairs of knobs that each changed the table in round 1,
// best singles' pairs first, at most kMaxPairFits, each fitted jointly from
// the better single's fit; checks, the best acceptable pair, its aliases.
bool fit_pairs(RobotSearch& s, const std::vector<SpeedRow>& rows, const SpeedFunction& speeds,
               const RobotProgress& say) {
  std::map<int, const KnobCandidate*> single;
  for (const KnobCandidate& c : s.candidates)
    if (c.round == 1) single[c.knob] = &c;
  std::vector<int> useful;   // knobs whose fit alone moved the gap by 1 % or more
  for (const auto& [k, c] : single)
    if (c->fit.gap < 0.99 * s.gap_before) useful.push_back(k);
  std::vector<PairCandidate> pairs;
  for (size_t i = 0; i < useful.size(); ++i)
    for (size_t j = i + 1; j < useful.size(); ++j) {
      int a = useful[i], b = useful[j];
      // a pair with an accepted knob was fitted jointly in round 2 already
      if (std::count(s.accepted.begin(), s.accepted.end(), a) || std::count(s.accepted.begin(), s.accepted.end(), b))
        continue;
      if (single[b]->fit.gap < single[a]->fit.gap) std::swap(a, b);
      PairCandidate p;
      p.a = a, p.b = b;
      p.single_a = single[a]->fit.gap, p.single_b = single[b]->fit.gap;
      pairs.push_back(p);
    }
  std::stable_sort(pairs.begin(), pairs.end(), [](const PairCandidate& x, const PairCandidate& y) {
    return x.single_a + x.single_b < y.single_a + y.single_b;
  });
  if (pairs.size() > size_t(kMaxPairFits)) pairs.resize(kMaxPairFits);
  if (pairs.empty()) return false;

  const double ref = s.gap_after;
  const double keep = 1 - kMinGainRobot;
  for (PairCandidate& p : pairs) {
    const std::string name = pair_name(p.a, p.b);
    p.fit = fit_new_knob(speeds, rows, single[p.a]->fit.st, p.b, {});
    say("pair " + name + " -> gap " + fmt_fixed(p.fit.gap));
    const double better_single = std::min(p.single_a, p.single_b);
    if (p.fit.gap > keep * ref) {
      p.why = short_cut(ref, p.fit.gap);
      continue;
    }
    if (p.fit.gap > keep * better_single) {
      // the better single alone does nearly as well: the other knob is not needed
      const int weaker = p.single_a <= p.single_b ? p.b : p.a;
      p.why = std::string(robot_knobs()[weaker].name) + " not needed: the other alone reaches " +
              fmt_fixed(better_single) + ", the pair cuts that by " + percent_cut(better_single, p.fit.gap) +
              " (< " + fmt_fixed(100 * kMinGainRobot, 0) + " %)";
      continue;
    }
    say("pair " + name + ": leave-one-row-out check");
    p.leave_one_out = leave_each_row_out(rows.size(), speeds, [&](const std::vector<bool>& mask) {
      return fit_knobs(speeds, rows, p.fit.st, mask, 20).st;   // from the pair's fit: a local refit
    });
    p.leave_one_out_gap = speed_gap(p.leave_one_out, rows);
    if (p.leave_one_out_gap > keep * ref) {
      p.why = "leave-one-row-out gap " + fmt_fixed(p.leave_one_out_gap) + " cuts the gap by only " +
              percent_cut(ref, p.leave_one_out_gap);
      continue;
    }
    p.acceptable = true;
    p.why = "fits; each knob needed";
  }

  int best = -1;
  for (size_t i = 0; i < pairs.size(); ++i)
    if (pairs[i].acceptable && (best < 0 || pairs[i].fit.gap < pairs[size_t(best)].fit.gap)) best = int(i);
  if (best >= 0) {
    PairCandidate& b = pairs[size_t(best)];
    b.accepted = true;
    b.why = "accepted";
    const size_t aliases_before = s.aliases.size();
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (int(i) == best || !pairs[i].acceptable) continue;
      pairs[i].why = "fits, but less well than the accepted pair";
      note_alias(s, b.fit.st, pairs[i].fit, speeds, "pair", &pairs[i].why);
    }
    if (s.aliases.size() > aliases_before) b.why = "accepted; the table cannot tell it from an alias (see aliases)";
    s.model = b.fit.st;
    s.accepted = {b.a, b.b};
    s.gap_after = b.fit.gap;
    s.leave_one_out = b.leave_one_out;
    s.leave_one_out_gap = b.leave_one_out_gap;
  }
  s.pairs = std::move(pairs);
  return best >= 0;
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
    const double gap_round = s.gap_after;
    bool took = false;
    for (size_t i = 0; i < cands.size(); ++i) {
      KnobCandidate& c = cands[i];
      const Knob& kb = robot_knobs()[c.knob];
      const double fac = c.fit.st.at(c.knob);
      const bool at_null = std::fabs(std::log(fac)) < 0.01;
      const bool at_bound = fac <= kb.lo * 1.01 || fac >= kb.hi / 1.01;
      if (i > 0) c.why = "not the best of the round";
      else if (at_null) c.why = "fitted to its nominal value";
      else if (c.fit.gap > (1 - kMinGainRobot) * s.gap_after) c.why = short_cut(s.gap_after, c.fit.gap);
      else c.accepted = true, c.why = "accepted";
      if (c.accepted && at_bound) c.why += " (at a bound of its range)";
      if (c.accepted) s.model = c.fit.st, s.gap_after = c.fit.gap, s.accepted.push_back(c.knob), took = true;
      // a runner-up that passes too and predicts the same table within its resolution: an alias
      if (i > 0 && took && !at_null && c.fit.gap <= (1 - kMinGainRobot) * gap_round)
        note_alias(s, s.model, c.fit, speeds, "knob", &c.why);
      s.candidates.push_back(c);
    }
    if (!took) break;
  }
  s.leave_one_out.assign(n, NAN);
  s.leave_one_out_gap = NAN;
  bool pair_taken = false;
  if (max_params >= 2 && s.accepted.size() < 2 && s.gap_after > kTableResolution) {
    say(std::string(s.accepted.empty() ? "no single knob accepted" : "the gap stays above the table's resolution") +
        ": pairs of knobs fitted jointly");
    pair_taken = fit_pairs(s, rows, speeds, say);
  }
  s.after = speeds(s.model);

  if (pair_taken)   // the pair replaced what the greedy rounds accepted: their candidates say so
    for (KnobCandidate& c : s.candidates)
      if (c.accepted) c.accepted = false, c.why += "; replaced by the pair " + pair_name(s.accepted[0], s.accepted[1]);
  // an alias recorded for a model that a later round or the pair stage changed
  // says nothing of the final one
  s.aliases.erase(std::remove_if(s.aliases.begin(), s.aliases.end(),
                                 [&](const Alias& a) { return a.chosen != s.model; }),
                  s.aliases.end());
  if (!s.accepted.empty() && n >= 3 && !pair_taken) {
    say("leave-one-row-out check");
    s.leave_one_out = leave_each_row_out(n, speeds, [&](const std::vector<bool>& mask) {
      KnobSetting st;   // the accepted knobs refitted from scratch, in their order
      for (int k : s.accepted) st = fit_new_knob(speeds, rows, st, k, mask).st;
      return st;
    });
    s.leave_one_out_gap = speed_gap(s.leave_one_out, rows);
  }
  const bool explained = s.gap_after <= kTableResolution;
  s.verdict = s.accepted.empty() ? (explained ? "no_missing_effect" : "unexplained")
                                 : (explained ? "explained" : "unexplained");
  return s;
}

}  // namespace chainsim
