// The calibration's greedy search (effect_search.h).
#include "analysis/calibration/effect_search.h"

#include <algorithm>
#include <set>

#include "analysis/calibration/regimes.h"
#include "analysis/calibration/text_format.h"

namespace chainsim {
namespace {

// every effect not in `used`, fitted onto cur, best first
std::vector<Candidate> fit_candidates(const FitProblem& p, const Fit& cur, const std::set<int>& used,
                                      const std::vector<int>& regime, const CalibrationProgress& say) {
  const Residual rc = run_model(p, model_config(p.datasheet, cur.effects, cur.x)).residual;
  std::vector<Candidate> cands;
  for (int e = 0; e < static_cast<int>(effect_catalogue().size()); ++e) {
    if (used.count(e)) continue;
    const Effect& ef = effect_catalogue()[e];
    Candidate c{e, fit_with_effect(p, cur, e), regime_signature(rc, regime, ef.regimes), false, {}};
    say("  candidate " + std::string(ef.name) + " = " + fmt_g(c.fit.x.back()) + ": held-out " +
        fmt_g(c.fit.held) + ", structured " + fmt_g(c.fit.gap) + " (signature " + fmt_g(c.signature, 3) + ")");
    cands.push_back(c);
  }
  std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
    return x.fit.gap != y.fit.gap ? x.fit.gap < y.fit.gap : x.signature > y.signature;
  });
  for (Candidate& c : cands) {
    const double g = 1.0 - c.fit.gap / cur.gap;
    c.why = "held-out structured error " + fmt_g(cur.gap) + " -> " + fmt_g(c.fit.gap) + " (" + fmt_g(100 * g, 3) +
            " %), NRMSE " + fmt_g(cur.held) + " -> " + fmt_g(c.fit.held);
  }
  return cands;
}

}  // namespace

EffectSearch search_effects(const FitProblem& p, const Fit& base, const std::vector<int>& regime,
                            const CalibrationProgress& say) {
  EffectSearch s;
  s.model = base;
  Fit& cur = s.model;
  std::set<int> used;
  while (cur.white > kWhiteMax && used.size() < effect_catalogue().size()) {
    std::vector<Candidate> cands = fit_candidates(p, cur, used, regime, say);
    Candidate& best = cands.front();
    const double gain = 1.0 - best.fit.gap / cur.gap;
    const Effect& be = effect_catalogue()[best.effect];
    if (best.fit.x.back() < 0.01 * (be.hi - be.lo)) {
      for (Candidate& c : cands) c.why += ": rejected";
      best.why += " (fitted to its null value)";
      say("the best candidate fits to its null value: stop");
      s.rounds.push_back(cands);
      break;
    }
    if (gain >= kMinGain && best.fit.held < cur.held) {
      best.accepted = true;
      best.why += ": best candidate, gain >= " + fmt_g(100 * kMinGain) + " %: accepted";
      for (size_t i = 1; i < cands.size(); ++i) cands[i].why += ": less than the best";
      used.insert(best.effect);
      cur = best.fit;
      say("accepted " + std::string(be.name) + " (held-out " + fmt_g(cur.held) + ", whiteness " +
          fmt_g(cur.white, 3) + ")");
      s.rounds.push_back(cands);
    } else {
      for (Candidate& c : cands) c.why += ": gain below " + fmt_g(100 * kMinGain) + " %: rejected";
      say("no candidate cuts the held-out error by " + fmt_g(100 * kMinGain) + " %: stop");
      s.rounds.push_back(cands);
      break;
    }
  }
  return s;
}

}  // namespace chainsim
