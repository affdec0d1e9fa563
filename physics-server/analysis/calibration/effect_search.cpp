// The calibration's greedy search (effect_search.h).
#include "analysis/calibration/effect_search.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "analysis/calibration/paired_runs.h"
#include "analysis/calibration/regimes.h"
#include "analysis/calibration/text_format.h"

namespace chainsim {
namespace {

std::string effect_label(int e) {
  const Effect& ef = effect_catalogue()[e];
  return std::string(ef.name) + (*ef.variant ? std::string(" (") + ef.variant + ")" : "");
}

int dof_of(int e) { return static_cast<int>(effect_catalogue()[e].params.size()); }

int channels(const FitProblem& p) { return p.m.has_current ? 2 : 1; }

// squared residuals on the training blocks (samples x channels)
double training_terms(const FitProblem& p) {
  double n = 0;
  for (size_t k = 0; k < p.split.block.size(); ++k) n += p.split.in(k, Samples::training);
  return n * channels(p);
}

std::string screen_words(const Candidate& c) {
  const Effect& ef = effect_catalogue()[c.effect];
  return std::string("not fitted in full: no gain") + (*ef.refines ? std::string(" on ") + ef.refines : "") +
         " after " + std::to_string(c.screen.after) + " model runs" +
         (ef.fit == EffectFit::frame_clock ? " of each clock's fit" : "") + " (training loss " + fmt_g(c.fit.train) +
         ", above " + fmt_g(c.screen.loss) + ")";
}

// a candidate fitted in full: valid, and not stopped at the screen
bool fitted_in_full(const Candidate& c) { return c.fit.valid && !c.screen.stopped; }

bool passes(const Candidate& c) {
  return fitted_in_full(c) && c.profile.excludes_null && c.held_out.significant && c.resolution >= kMinResolution;
}

// both tests of every candidate against ref, best held-out gain first
void test_candidates(const FitProblem& p, const Fit& ref, std::vector<Candidate>* cands) {
  const int k = static_cast<int>(cands->size());
  for (Candidate& c : *cands) {
    c.profile = profile_test(ref.sse_train, c.fit.sse_train, training_terms(p), c.fit.rho_train, dof_of(c.effect));
    c.held_out = held_out_test(ref.loss, c.fit.loss, c.fit.rho_held, p.split, channels(p), k, dof_of(c.effect));
    c.why = "LR " + fmt_g(c.profile.stat) + (c.profile.excludes_null ? " >= " : " < ") + fmt_g(c.profile.crit) +
            " (interval " + (c.profile.excludes_null ? "excludes" : "includes") + " the null), held-out gain " +
            fmt_g(c.held_out.gain, 3) + "/sample, held-out LR " + fmt_g(c.held_out.stat, 4) +
            (c.held_out.significant ? " >= " : " < ") + fmt_g(c.held_out.crit, 3) +
            ", change where it acts (99th percentile) " + fmt_g(c.resolution, 3) +
            (c.resolution >= kMinResolution ? " >= " : " < ") + fmt_g(kMinResolution, 2) + " noise";
    if (!c.fit.valid) c.why = "no frame clock fits the set-point changes' delays";
    if (c.screen.stopped) c.why = screen_words(c);
    if (c.second_start_skipped)
      c.why += " (from its first start only: its effect's held-out gain there " + fmt_g(c.first_gain, 3) +
               "/sample, below " + fmt_g(kSecondStartShare, 2) + " of the round's best " +
               fmt_g(c.round_first_gain, 3) + ")";
    c.accepted = false;
  }
  std::stable_sort(cands->begin(), cands->end(), [](const Candidate& a, const Candidate& b) {
    if (a.fit.valid != b.fit.valid) return a.fit.valid;
    return a.held_out.gain > b.held_out.gain;
  });
}

// the candidate of the form that `ef` refines, fitted this round (or none)
template <class Candidates>
auto* refined_form(Candidates& cands, const Effect& ef) {
  for (auto& c : cands) {
    const Effect& s = effect_catalogue()[c.effect];
    if (std::string(s.name) == ef.name && std::string(s.variant) == ef.refines) return &c;
  }
  return static_cast<decltype(&cands[0])>(nullptr);
}

// whether fit f (of `dof` parameters more than ref) predicts the held-out
// blocks better than ref by the held-out test at the plain 5 % level (no
// correction for the number of candidates, which acceptance applies)
bool predicts_held_out(const FitProblem& p, const Fit& ref, const Fit& f, int dof) {
  return held_out_test(ref.loss, f.loss, f.rho_held, p.split, channels(p), 1, dof).significant;
}

// whether the form that `ef` refines, fitted this round, shows the effect:
// its profile interval excludes the null and it predicts the held-out blocks
// better by the held-out test at the plain 5 % level (a screen: no
// correction for the number of candidates, which acceptance applies). A
// frame clock needs only the first: where the pulse widths of a
// falling-edge decoder spread the delays, the plain clock found is a
// compromise that fits the training blocks and may not predict the
// held-out ones, which the refining form, fitted from its own clocks too,
// then does; and where no plain clock is found at all, the refining form
// is tried all the same (its corrected delays may make one)
bool shows_effect(const FitProblem& p, const Fit& ref, const std::vector<Candidate>& cands, const Effect& ef) {
  const Candidate* c = refined_form(cands, ef);
  if (!c) return false;
  const bool clock = ef.fit == EffectFit::frame_clock;
  if (clock && !c->fit.valid) return true;
  const int dof = dof_of(c->effect);
  return fitted_in_full(*c) &&
         profile_test(ref.sse_train, c->fit.sse_train, training_terms(p), c->fit.rho_train, dof).excludes_null &&
         (clock || predicts_held_out(p, ref, c->fit, dof));
}

// of the passing candidate `best` and the other variants of its effect, the
// form to name: a variant with more parameters must beat each simpler one
// that passes by the same tests; where it does not, the simpler one (the best
// held-out gain first) is judged the same way in its place. The report
// compares the form named with the best of the other forms
size_t choose_variant(const FitProblem& p, std::vector<Candidate>& cands, size_t best, VariantChoice* vc) {
  const std::string name = effect_catalogue()[cands[best].effect].name;
  // the other valid forms of the effect, best held-out gain first (the candidates' order)
  auto others = [&](size_t b) {
    std::vector<size_t> o;
    for (size_t s = 0; s < cands.size(); ++s)
      if (s != b && fitted_in_full(cands[s]) && name == effect_catalogue()[cands[s].effect].name) o.push_back(s);
    return o;
  };
  vc->effect = name;
  std::string richer, why;  // a richer form passed over, and why
  double back = 0;
  for (bool moved = true; moved;) {
    moved = false;
    for (size_t s : others(best)) {
      const Candidate& b = cands[best];
      const Candidate& o = cands[s];
      const int extra = dof_of(b.effect) - dof_of(o.effect);
      if (extra <= 0 || !passes(o)) continue;
      const HeldOutTest ho = held_out_test(o.fit.loss, b.fit.loss, b.fit.rho_held, p.split, channels(p), 1, extra);
      const ProfileTest pt = profile_test(o.fit.sse_train, b.fit.sse_train, training_terms(p), b.fit.rho_train, extra);
      if (ho.significant && pt.excludes_null) continue;
      // the richer form does not earn its parameters: the simpler one
      richer = effect_catalogue()[b.effect].variant;
      why = richer + " does not beat it (held-out LR " + fmt_g(ho.stat, 4) + ", LR " + fmt_g(pt.stat) + " for " +
            std::to_string(extra) + " more parameter" + (extra > 1 ? "s" : "") + ")";
      back = held_out_test(b.fit.loss, o.fit.loss, o.fit.rho_held, p.split, channels(p), 1, 1).stat;
      best = s;
      moved = true;
      break;
    }
  }
  vc->chosen = effect_catalogue()[cands[best].effect].variant;
  if (!richer.empty()) {
    *vc = {name, vc->chosen, richer, back, false, why};
    return best;
  }
  const std::vector<size_t> o = others(best);
  if (o.empty()) return best;
  const Candidate& b = cands[best];
  const Candidate& c = cands[o.front()];
  const HeldOutTest ho = held_out_test(c.fit.loss, b.fit.loss, b.fit.rho_held, p.split, channels(p), 1,
                                       std::max(1, dof_of(b.effect) - dof_of(c.effect)));
  vc->other = effect_catalogue()[c.effect].variant;
  vc->t = ho.stat;
  vc->distinguished = ho.significant;
  vc->why = std::string(ho.significant ? "fits better than " : "not distinguished from ") + vc->other +
            " on held-out data (LR " + fmt_g(ho.stat, 4) + " against " + fmt_g(ho.crit, 3) + ")";
  return best;
}

}  // namespace

bool both_starts_at_once(int effect) {
  const Effect& ef = effect_catalogue()[effect];
  return ef.fit != EffectFit::smooth || *ef.refines;
}

bool run_second_start(double effect_first_gain, double round_first_gain) {
  return round_first_gain <= 0 || effect_first_gain >= kSecondStartShare * round_first_gain;
}

GiveUp screen_for(const FitProblem& p, const Fit& ref, int e, const Fit* refined) {
  GiveUp g;
  const double n = static_cast<double>(param_count(ref.effects) + dof_of(e));
  g.after = static_cast<int>(kScreenSets * (2 * n + 1));
  // against the refined form, where it predicts the held-out blocks better
  // than ref (at the plain 5 % level): its extra parameters only. Where it
  // does not, the refining form need not beat it on the training blocks to
  // be named (choose_variant weighs only forms that pass), so it is screened
  // against ref as any other candidate
  if (refined && (!refined->valid || !predicts_held_out(p, ref, *refined, dof_of(refined->effects.back()))))
    refined = nullptr;
  const Fit& against = refined ? *refined : ref;
  const int dof = refined ? dof_of(e) - dof_of(refined->effects.back()) : dof_of(e);
  const double terms = training_terms(p), samples = terms / channels(p);
  const double rho = std::min(against.rho_train, 0.999);   // as the held-out test bounds it
  const double inflation = (1 + rho) / (1 - rho);
  g.loss = profiled_sse_at(against.sse_train, screen_crit(dof) * inflation, terms) / samples;
  return g;
}

double effect_resolution(ModelRuns& runs, const FitProblem& p, const Fit& with, const Fit& without_effects, int effect,
                         const std::vector<int>& regime) {
  if (!with.valid) return 0;
  const std::vector<double> xs(with.x.begin(), with.x.begin() + param_count(without_effects.effects));
  Residual a, b;
  run_paired(
      runs, {[&](ModelRuns& runs) { a = run_model(runs, p, model_config(p.datasheet, with.effects, with.x)).residual; },
             [&](ModelRuns& runs) {
               b = run_model(runs, p, model_config(p.datasheet, without_effects.effects, xs)).residual;
             }});
  // the effect's regimes and the 40 ms after each set-point change, whose
  // label wins over the motion regimes (a short move is all step onset)
  std::vector<std::string> names = effect_catalogue()[effect].regimes;
  for (int r : {kStepOnset, kReversal}) names.push_back(regime_names()[r]);
  std::vector<double> change;
  for (size_t k = 0; k < a.size() && k < regime.size(); ++k) {
    if (std::find(names.begin(), names.end(), regime_names()[regime[k]]) == names.end()) continue;
    const double da = (a.angle[k] - b.angle[k]) / p.noise.angle;
    const double di = a.has_current ? (a.current[k] - b.current[k]) / p.noise.current : 0.0;
    change.push_back(std::sqrt((da * da + di * di) / a.channels()));
  }
  return resolved_change(std::move(change));
}

double resolved_change(std::vector<double> change) {
  if (change.empty()) return 0.0;
  const auto k = static_cast<size_t>(std::floor(kResolutionQuantile * static_cast<double>(change.size() - 1)));
  std::nth_element(change.begin(), change.begin() + static_cast<long>(k), change.end());
  return change[k];
}

NoiseScale round_noise(ModelRuns& runs, const FitProblem& p, const Fit& cur) {
  return white_noise_scale(run_model(runs, p, model_config(p.datasheet, cur.effects, cur.x)).residual, p.split);
}

FitProblem with_noise(const FitProblem& p, const NoiseScale& noise) {
  FitProblem q = p;
  q.noise = noise;
  return q;
}

Reference fit_reference(ModelRuns& runs, const FitProblem& p, const Fit& cur, const CalibrationProgress& say) {
  Reference r;
  r.fit = evaluate_fit(runs, p, cur.effects, cur.x);
  r.fit.held_ci = cur.held_ci;
  r.fit = refit_from_starts(runs, p, r.fit, {cur.x, datasheet_start(cur.x)}, kMaxEvalBase);
  {  // a frame clock found before the other effects: fitted again with them
    const double before = r.fit.train;
    r.fit = refit_frame_clock(runs, p, r.fit);
    if (r.fit.train < before) say("  the frame clock fitted again on top of the other effects: training loss " +
                                  fmt_g(before) + " -> " + fmt_g(r.fit.train));
  }
  r.residual = run_model(runs, p, model_config(p.datasheet, r.fit.effects, r.fit.x)).residual;
  return r;
}

namespace {

// The candidates' fits are independent of each other: each stage below runs
// them two at a time (run_paired), each writing its own slot and its own
// lines, and the lines are said in the order of the slots.
using Lines = std::vector<std::string>;

void say_all(const CalibrationProgress& say, const std::vector<Lines>& lines) {
  for (const Lines& ls : lines)
    for (const std::string& l : ls) say(l);
}

// the rest of a candidate fitted in full: its resolution and its line
void finish_candidate(ModelRuns& runs, const FitProblem& p, const Fit& ref, const std::vector<int>& regime,
                      Candidate& c, Lines& out) {
  c.resolution = effect_resolution(runs, p, c.fit, ref, c.effect, regime);
  out.push_back("  candidate " + effect_label(c.effect) + " = " + fmt_g(c.fit.x[param_count(ref.effects)]) +
                ": training loss " + fmt_g(c.fit.train) + ", held-out NRMSE " + fmt_g(c.fit.held) + " (" +
                std::to_string(c.runs) + " model runs" + (c.second_start_skipped ? ", its first start only" : "") +
                ")");
}

// a candidate's fit, screened (screen_for) or not: from both starts and
// finished where both_starts_at_once, else from its first start alone
// (the datasheet start is decided in fit_second_starts)
Candidate fit_candidate(ModelRuns& runs, const FitProblem& p, const Reference& ref, const std::vector<int>& regime,
                        int e, bool screened, const Fit* refined, Lines& out) {
  const Effect& ef = effect_catalogue()[e];
  const int runs_candidate = runs.count();
  Candidate c;
  c.effect = e;
  c.signature = regime_signature(ref.residual, regime, ef.regimes);
  c.screen = screen_for(p, ref.fit, e, refined);
  GiveUp* screen = screened ? &c.screen : nullptr;
  const bool both = both_starts_at_once(e);
  c.fit = both ? fit_with_effect(runs, p, ref.fit, e, screen, refined)
               : fit_effect_start(runs, p, ref.fit, e, 0, screen, refined);
  c.runs = runs.count() - runs_candidate;
  if (c.screen.stopped) {
    out.push_back("  candidate " + effect_label(e) + " " + screen_words(c));
  } else if (both) {
    finish_candidate(runs, p, ref.fit, regime, c, out);
  }
  return c;
}

}  // namespace

std::vector<Candidate> fit_candidates(ModelRuns& runs, const FitProblem& p, const Reference& ref,
                                      const std::vector<int>& regime, const std::set<std::string>& used,
                                      const CalibrationProgress& say) {
  // the forms not yet used and not refining another, in the catalogue's
  // order. One task per effect fits its forms in that order: a form is
  // screened unless an earlier form of its effect passed the screen, and
  // then every form of an effect that one of its forms shows is fitted in
  // full (the form is chosen between full fits)
  std::vector<Candidate> cands;
  std::vector<std::vector<size_t>> effect_forms;   // per effect, its candidates
  {
    std::map<std::string, size_t> effect_index;
    for (int e = 0; e < static_cast<int>(effect_catalogue().size()); ++e) {
      const Effect& ef = effect_catalogue()[e];
      if (used.count(ef.name) || *ef.refines) continue;
      const auto [it, fresh] = effect_index.emplace(ef.name, effect_forms.size());
      if (fresh) effect_forms.emplace_back();
      effect_forms[it->second].push_back(cands.size());
      cands.emplace_back().effect = e;
    }
  }
  // the longest work first, so that the last task left alone is short: a
  // frame clock (both starts, each clock), then the effects of more forms
  auto work = [&](const std::vector<size_t>& forms) {
    return std::make_pair(both_starts_at_once(cands[forms.front()].effect), forms.size());
  };
  std::stable_sort(effect_forms.begin(), effect_forms.end(),
                   [&](const std::vector<size_t>& a, const std::vector<size_t>& b) { return work(a) > work(b); });
  std::vector<Lines> lines(cands.size()), again_lines(cands.size());
  run_paired_each(runs, effect_forms.size(), [&](ModelRuns& runs, size_t k) {
    const std::vector<size_t>& forms = effect_forms[k];
    bool shown = false;   // a form so far passed the screen
    for (size_t i : forms) {
      cands[i] = fit_candidate(runs, p, ref, regime, cands[i].effect, !shown, nullptr, lines[i]);
      shown = shown || !cands[i].screen.stopped;
    }
    for (size_t i : forms)
      if (shown && cands[i].screen.stopped)
        cands[i] = fit_candidate(runs, p, ref, regime, cands[i].effect, false, nullptr, again_lines[i]);
  });
  say_all(say, lines);
  say_all(say, again_lines);
  return cands;
}

void fit_second_starts(ModelRuns& runs, const FitProblem& p, const Fit& ref, const std::vector<int>& regime,
                       std::vector<Candidate>* cands, const CalibrationProgress& say) {
  std::map<std::string, double> effect_gain;   // per effect, its forms' best first-start held-out gain
  double best = -1e300;
  std::vector<size_t> second;
  for (size_t i = 0; i < cands->size(); ++i) {
    const Candidate& c = (*cands)[i];
    if (both_starts_at_once(c.effect) || c.screen.stopped) continue;
    const double g = held_out_test(ref.loss, c.fit.loss, c.fit.rho_held, p.split, channels(p), 1, 1).gain;
    const auto [it, fresh] = effect_gain.emplace(effect_catalogue()[c.effect].name, g);
    if (!fresh) it->second = std::max(it->second, g);
    best = std::max(best, g);
    second.push_back(i);
  }
  std::vector<Lines> second_lines(second.size());
  run_paired_each(runs, second.size(), [&](ModelRuns& runs, size_t k) {
    Candidate& c = (*cands)[second[k]];
    const int runs_before = runs.count();
    c.first_gain = effect_gain.at(effect_catalogue()[c.effect].name);
    c.round_first_gain = best;
    c.second_start_skipped = !run_second_start(c.first_gain, best);
    if (!c.second_start_skipped) {
      Fit f = fit_effect_start(runs, p, ref, c.effect, 1);
      if (f.train < c.fit.train) c.fit = std::move(f);
    }
    c.runs += runs.count() - runs_before;
    finish_candidate(runs, p, ref, regime, c, second_lines[k]);
  });
  say_all(say, second_lines);
}

void fit_refining_forms(ModelRuns& runs, const FitProblem& p, const Reference& ref, const std::vector<int>& regime,
                        const std::set<std::string>& used, std::vector<Candidate>* cands,
                        const CalibrationProgress& say) {
  struct Refining {
    int effect;
    bool fitted;
    Lines lines;
    Candidate c;
  };
  std::vector<Refining> rf;
  for (int e = 0; e < static_cast<int>(effect_catalogue().size()); ++e) {
    const Effect& ef = effect_catalogue()[e];
    if (used.count(ef.name) || !*ef.refines) continue;
    rf.push_back({e, shows_effect(p, ref.fit, *cands, ef), {}, {}});
    if (!rf.back().fitted)
      rf.back().lines.push_back("  candidate " + effect_label(e) + " not fitted: " + ef.refines +
                                " shows no effect this round");
  }
  std::vector<size_t> fit;
  for (size_t k = 0; k < rf.size(); ++k)
    if (rf[k].fitted) fit.push_back(k);
  run_paired_each(runs, fit.size(), [&](ModelRuns& runs, size_t k) {
    Refining& r = rf[fit[k]];
    r.c = fit_candidate(runs, p, ref, regime, r.effect, true, &refined_form(*cands, effect_catalogue()[r.effect])->fit,
                        r.lines);
  });
  // a frame clock's refining form fitted in full: the plain clock fitted
  // again from its solution, kept where that fits the training blocks
  // better than the plain clock's own fit (servo_fit.h, refit_plain_clock)
  std::vector<std::pair<Candidate*, const Candidate*>> again;   // (plain, refining)
  for (size_t k : fit) {
    const Refining& r = rf[k];
    if (effect_catalogue()[r.effect].fit != EffectFit::frame_clock || !fitted_in_full(r.c)) continue;
    if (Candidate* c = refined_form(*cands, effect_catalogue()[r.effect])) again.push_back({c, &r.c});
  }
  std::vector<Lines> again_lines(again.size());
  run_paired_each(runs, again.size(), [&](ModelRuns& runs, size_t k) {
    Candidate& c = *again[k].first;
    const int runs_before = runs.count();
    Fit f = refit_plain_clock(runs, p, ref.fit, c.effect, again[k].second->fit);
    c.runs += runs.count() - runs_before;
    if (c.fit.valid && !(f.train < c.fit.train)) return;
    again_lines[k].push_back("  candidate " + effect_label(c.effect) + " fitted again from " +
                             effect_label(again[k].second->effect) + "'s solution: training loss " +
                             (c.fit.valid ? fmt_g(c.fit.train) : std::string("(no clock)")) + " -> " +
                             fmt_g(f.train));
    c.fit = std::move(f);
    c.screen.stopped = false;
    finish_candidate(runs, p, ref.fit, regime, c, again_lines[k]);
  });
  for (Refining& r : rf) {
    for (const std::string& l : r.lines) say(l);
    if (r.fitted) cands->push_back(std::move(r.c));
  }
  say_all(say, again_lines);
}

Selection select_candidate(ModelRuns& runs, const FitProblem& p, const Fit& ref, std::vector<Candidate>* cands,
                           const CalibrationProgress& say) {
  Selection sel;
  sel.reference = ref;
  for (int attempt = 0; attempt < 3; ++attempt) {
    test_candidates(p, sel.reference, cands);
    const auto it = std::find_if(cands->begin(), cands->end(), passes);
    if (it == cands->end()) break;
    // a re-fit of the current model alone from where the candidate ended:
    // if that is better, the candidate's gain was the optimiser's
    const Candidate& b = *it;
    const std::vector<double> xs(b.fit.x.begin(), b.fit.x.begin() + param_count(sel.reference.effects));
    Fit alt = fit_model(runs, p, sel.reference.effects, xs, Samples::training, kMaxEvalBase);
    alt.held_ci = sel.reference.held_ci;
    if (alt.train < sel.reference.train * (1 - 1e-6)) {
      say("  the reference re-fitted from " + effect_label(b.effect) + "'s solution is better (" +
          fmt_g(sel.reference.train) + " -> " + fmt_g(alt.train) + "): candidates tested again");
      sel.reference = std::move(alt);
      sel.reference_refit = true;
      continue;
    }
    sel.variant = VariantChoice{};
    sel.chosen = static_cast<long>(choose_variant(p, *cands, it - cands->begin(), &sel.variant));
    break;
  }
  if (sel.chosen < 0) {
    for (Candidate& c : *cands) c.why += ": rejected";
    return sel;
  }
  Candidate& a = (*cands)[sel.chosen];
  a.accepted = true;
  a.why += ": accepted";
  for (Candidate& c : *cands)
    if (!c.accepted) c.why += passes(c) ? ": passes, but another is better" : ": rejected";
  const Effect& ae = effect_catalogue()[a.effect];
  if (*ae.variant && sel.variant.chosen.empty()) sel.variant = {ae.name, ae.variant, "", 0, false, "the only variant fitted"};
  return sel;
}

EffectSearch search_effects(ModelRuns& runs, const FitProblem& problem, const Fit& base, const std::vector<int>& regime,
                            SearchState& state, const CalibrationProgress& say) {
  const int runs_before = runs.count();
  EffectSearch s;
  Fit cur = base;
  std::set<std::string> used;
  for (;;) {
    SearchRound round;
    // the loss's unit: the white noise left by the current model; the
    // round's fits take it with the problem
    const int round_runs = runs.count();
    state.noise = round.noise = round_noise(runs, problem, cur);
    const FitProblem p = with_noise(problem, state.noise);
    const Reference ref = fit_reference(runs, p, cur, say);
    say("round " + std::to_string(s.rounds.size() + 1) + ": reference re-fitted from 2 starts, training loss " +
        fmt_g(ref.fit.train) + ", held-out NRMSE " + fmt_g(ref.fit.held) + ", whiteness " + fmt_g(ref.fit.white, 3) +
        " (" + std::to_string(runs.count() - round_runs) + " model runs)");
    std::vector<Candidate> cands = fit_candidates(runs, p, ref, regime, used, say);
    fit_second_starts(runs, p, ref.fit, regime, &cands, say);
    // then a form that refines another, where that form, as fitted in the
    // end, shows the effect (every decision is taken before any of these fits)
    fit_refining_forms(runs, p, ref, regime, used, &cands, say);
    if (cands.empty()) {
      round.reference = ref.fit;
      s.rounds.push_back(std::move(round));
      break;
    }
    Selection sel = select_candidate(runs, p, ref.fit, &cands, say);
    round.reference = sel.reference;
    round.reference_refit = sel.reference_refit;
    if (sel.chosen < 0) {
      say("no candidate passes both tests: stop");
      round.candidates = std::move(cands);
      s.rounds.push_back(std::move(round));
      break;
    }
    const Candidate& a = cands[sel.chosen];
    const Effect& ae = effect_catalogue()[a.effect];
    if (*ae.variant) s.variants.push_back(sel.variant);
    used.insert(ae.name);
    s.before.push_back(sel.reference);
    cur = a.fit;
    say("accepted " + effect_label(a.effect) + " (held-out NRMSE " + fmt_g(cur.held) + ", whiteness " +
        fmt_g(cur.white, 3) + ")");
    round.candidates = std::move(cands);
    s.rounds.push_back(std::move(round));
  }
  s.model = s.rounds.back().reference;
  state.model_runs += runs.count() - runs_before;
  return s;
}

}  // namespace chainsim
