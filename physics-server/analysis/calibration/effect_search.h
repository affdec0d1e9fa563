// The calibration's greedy search, round by round: the current model is
// re-fitted from several starts (the reference), every catalogue effect not
// yet in it is fitted on top (each variant of an effect separately; from the
// reference's base, screened, then from the datasheet's where
// run_second_start says; the forms that refine another last), and the
// candidate with the largest held-out gain that passes both tests of
// selection_rule.h is accepted, after the reference has been re-fitted from
// that candidate's own solution too. Of an effect's variants the one that
// fits better on held-out data is named; a variant with more parameters must
// beat the simpler one by the same tests. The search stops when no candidate
// passes. docs/calibration.md, "Method".
#pragma once

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "analysis/calibration/selection_rule.h"
#include "analysis/calibration/servo_fit.h"

namespace chainsim {

constexpr double kWhiteMax = 1.6;    // whiteness ratio at or below which a residual is noise

// a progress line (the CLI prints it on stderr)
using CalibrationProgress = std::function<void(const std::string&)>;

struct Candidate {
  int effect = 0;        // catalogue index
  Fit fit;
  double signature = 0;  // regime_signature of the reference's residual in the effect's regimes
  double resolution = 0; // its change where it acts (99th percentile), white-noise units (effect_resolution)
  ProfileTest profile;
  HeldOutTest held_out;
  bool accepted = false;
  GiveUp screen;          // the screen of its fit (effect_search.cpp); screen.stopped: fit is that start's best
  double first_gain = 0;             // its effect's best first-start held-out gain (per sample)
  double round_first_gain = 0;       // the round's best of those
  bool second_start_skipped = false; // the datasheet start not run (run_second_start)
  int runs = 0;                      // model runs of its fit
  std::string why;       // the decision, in words
};

// how the accepted effect's form was chosen among its variants
struct VariantChoice {
  std::string effect, chosen, other;
  double t = 0;             // held-out likelihood ratio of the chosen against the other (as its reference)
  bool distinguished = false;
  std::string why;
};

struct SearchRound {
  Fit reference;                      // the current model re-fitted from several starts
  NoiseScale noise;                   // the loss's unit this round
  std::vector<Candidate> candidates;  // best held-out gain first
  bool reference_refit = false;       // the reference improved from a candidate's solution
};

struct EffectSearch {
  Fit model;                          // the reference of the last round, or the base with the accepted effects
  std::vector<SearchRound> rounds;
  std::vector<VariantChoice> variants;   // per accepted effect with variants
  std::vector<Fit> before;            // per accepted effect (in model.effects' order): the model without it
};

// the screen of a candidate's fit (selection_rule.h, screen_crit): after
// kScreenSets times BOBYQA's interpolation set (2n + 1 model runs for the n
// parameters of ref plus the effect) its first start must have reached the
// training loss at which the profile test's statistic against ref is
// screen_crit (with ref's correlation inflation), or it stops there (a frame
// clock: each clock found, in its first fit; servo_fit.h). With
// refined (the fit of the form that effect refines), where that fit
// predicts the held-out blocks better than ref at the plain 5 % level, the
// loss is the one at which its extra parameters' statistic against that fit
// is screen_crit.
GiveUp screen_for(const FitProblem& p, const Fit& ref, int effect, const Fit* refined = nullptr);

// whether a candidate of the smooth kind is also fitted from the datasheet
// start: where the best first-start held-out gain of its effect's forms is
// at least kSecondStartShare of the round's best first-start gain (or no
// first start gained). A candidate that far behind does not win its round
// from the datasheet start: in the 66 pair records of seeds 100-102 every
// accepted candidate had at least 0.43 of its round's best from its first
// start alone (docs/calibration.md, Method, 5)
constexpr double kSecondStartShare = 0.25;
bool run_second_start(double effect_first_gain, double round_first_gain);
// the candidates fitted from both starts at once, whatever the others do: a
// frame clock (its own fit) and a form that refines another
bool both_starts_at_once(int effect);

// how much the effect of candidate `with` changes the response where it acts:
// over the samples of the effect's regimes and of the step onsets and
// reversals (their label hides the motion regimes), the change (model with it
// - the same model without it), each channel in its white-noise unit, the
// channels pooled like the loss; its 99th percentile (resolved_change). Below
// 1 the effect stays under the noise at all but a few of the samples it acts
// on: a measurement of that noise does not resolve it, and a likelihood gain
// over thousands of samples is the model's sub-noise mismatch with the
// measured system, not the effect (kMinResolution). A percentile, not the
// rms: an effect that acts hard on a few moves (a current limit on the
// fastest) and not on the rest of its regime's samples is resolved there.
constexpr double kMinResolution = 1.0;
constexpr double kResolutionQuantile = 0.99;
double effect_resolution(ModelRuns& runs, const FitProblem& p, const Fit& with, const Fit& without_effects, int effect,
                         const std::vector<int>& regime);
// the kResolutionQuantile quantile of the per-sample changes (0 for none)
double resolved_change(std::vector<double> change);

// The search's stages, in the order of a round; each takes the problem as
// it is (const: the round's loss unit is in it, with_noise) and gives what
// it found. The model runs they make are asked on the strand `runs` and
// counted there (ModelRuns::count, paired_runs.h).

// what the search changes as it goes, owned by its caller: the loss's unit
// (the white noise left by the current model, set each round) and the model
// runs the search made
struct SearchState {
  NoiseScale noise;
  int model_runs = 0;
};

// the loss's unit for a round: the white noise of the current model's
// residual (one model run)
NoiseScale round_noise(ModelRuns& runs, const FitProblem& p, const Fit& cur);
// the problem with that unit: a copy, so that the problem given stays as it
// was and every fit of the round sees one unit (a record of 20 000 samples
// copies in well under a millisecond, next to a round's hundreds of model
// runs of about one each)
FitProblem with_noise(const FitProblem& p, const NoiseScale& noise);

// 1. the reference: the current model re-fitted from two starts (its own
// values and the datasheet base), its frame clock (if any, not found last)
// fitted again on top of the others; and its residual on all samples (the
// candidates' regime signatures)
struct Reference {
  Fit fit;
  Residual residual;
};
Reference fit_reference(ModelRuns& runs, const FitProblem& p, const Fit& cur, const CalibrationProgress& say);

// 2. the candidates: every form of the effects not in `used` that refines no
// other, in the catalogue's order, fitted on top of the reference; a form is
// screened (screen_for) unless an earlier form of its effect passed the
// screen, and every form of an effect that one of its forms shows is fitted
// in full. Smooth forms from their first start only (3 adds the second);
// frame clocks from both and finished (their resolution)
std::vector<Candidate> fit_candidates(ModelRuns& runs, const FitProblem& p, const Reference& ref,
                                      const std::vector<int>& regime, const std::set<std::string>& used,
                                      const CalibrationProgress& say);

// 3. the datasheet starts of the smooth candidates that passed the screen,
// where run_second_start says; each of those candidates finished (its
// resolution and its line)
void fit_second_starts(ModelRuns& runs, const FitProblem& p, const Fit& ref, const std::vector<int>& regime,
                       std::vector<Candidate>* cands, const CalibrationProgress& say);

// 4. the forms that refine another (not in `used`), each fitted from the
// solution of the form it refines, where that form as fitted in 2-3 shows
// the effect (shows_effect: for a frame clock, on the training blocks, or
// no clock found, when it is fitted from its own clocks), and screened
// against it where it passes the held-out test, else against the
// reference (screen_for); appended to cands, a frame clock's even where
// no clock of its own is found either (it counts among the candidates of
// the held-out test's correction). Where a frame clock's refining form is
// fitted in full, the plain clock's candidate is fitted again from its
// solution and replaced where that is better (servo_fit.h, refit_plain_clock)
void fit_refining_forms(ModelRuns& runs, const FitProblem& p, const Reference& ref, const std::vector<int>& regime,
                        const std::set<std::string>& used, std::vector<Candidate>* cands,
                        const CalibrationProgress& say);

// 5. the selection: both tests of every candidate against the reference
// (cands sorted best held-out gain first, each with its decision in words);
// the reference re-fitted from the best passing candidate's own solution,
// and the candidates tested again against it where that is better (at most
// twice); of the passing effect's forms, the one to name (choose_variant)
struct Selection {
  Fit reference;                 // the reference the candidates were last tested against
  bool reference_refit = false;  // it improved from a candidate's solution
  long chosen = -1;              // the accepted candidate (-1: none passes)
  VariantChoice variant;         // its form's choice (an effect with variants)
};
Selection select_candidate(ModelRuns& runs, const FitProblem& p, const Fit& ref, std::vector<Candidate>* cands,
                           const CalibrationProgress& say);

// the search from the refitted base, round by round (1-5) until no
// candidate passes; regime: classify_regimes of the measurement. state.noise
// is the last round's loss unit at the end, state.model_runs counts the
// search's model runs on top of what it was
EffectSearch search_effects(ModelRuns& runs, const FitProblem& p, const Fit& base, const std::vector<int>& regime,
                            SearchState& state, const CalibrationProgress& say);

}  // namespace chainsim
