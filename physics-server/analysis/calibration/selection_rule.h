// When the calibration may add an effect: two tests of a candidate (the
// current model plus the effect) against the reference (the current model
// re-fitted alone from the same starts, i.e. the profile at the effect's null
// value). docs/calibration.md, "Method".
//
//  1. Profile-likelihood interval: the effect's 95 % interval excludes its
//     null value when the likelihood-ratio statistic on the training blocks,
//     divided by the residual's correlation inflation (1 + rho) / (1 - rho),
//     reaches the chi-square 95 % point for the effect's number of parameters.
//  2. Held-out likelihood: on the held-out blocks (not fitted) the
//     likelihood ratio (reference against candidate), divided by the
//     candidate's held-out correlation inflation, must reach the chi-square point at 5 %
//     divided by the number of candidates compared (Bonferroni) for the
//     effect's number of parameters. A parameter that only fits noise loses
//     on held-out data (its expected held-out difference is negative), so
//     the improvement must beat what a re-fit of the current model alone
//     achieves, and one of many candidates fitting noise does not pass. A
//     t test over batches of the held-out data was tried first: an effect
//     that acts at a few events (frame edges, reversals) concentrates its
//     gain in a few batches and never reached significance.
//
// Both ratios are Gaussian likelihoods whose variance is profiled per model:
// each model's variance is its own mean squared residual on the samples
// compared, floored at the white noise (the loss's unit). With residuals at
// the noise, the ratio is the drop of the summed loss in noise units; with a
// misfit no catalogue effect models (a record without noise, a generator the
// model only approximates) the misfit counts as that model's noise, so a
// candidate that trims a few percent off it is no evidence. A fixed unit of
// the white noise alone counted such a trim as hundreds of noise variances.
#pragma once

#include <string>
#include <vector>

#include "analysis/calibration/residual_stats.h"

namespace chainsim {

constexpr double kTestLevel = 0.05;

// upper quantiles: P(Z > z) = p for a standard normal; P(T > t) = p for
// Student's t with dof degrees of freedom; the chi-square 95 % point (dof 1..8)
double normal_upper_quantile(double p);
double student_t_upper_quantile(double p, int dof);
double chi_square_95(int dof);
// the upper quantile P(X > x) = p of a chi-square with dof degrees of freedom
// (Wilson-Hilferty: within 3 % for dof >= 1 at these tails)
double chi_square_upper_quantile(double p, int dof);

struct ProfileTest {
  double stat = 0;       // likelihood-ratio statistic, correlation-corrected
  double crit = 0;       // chi-square 95 % point
  double inflation = 1;  // (1 + rho) / (1 - rho)
  int dof = 1;
  bool excludes_null = false;
};
// sse_*: summed loss (noise units) on the training blocks; terms: its number
// of squared residuals (samples x channels)
ProfileTest profile_test(double sse_ref, double sse_cand, double terms, double rho_cand, int dof);

struct HeldOutTest {
  double gain = 0;       // mean loss difference per held-out sample (reference - candidate), noise units
  double stat = 0;       // likelihood ratio / inflation
  double crit = 0;       // the chi-square point at kTestLevel / comparisons
  double inflation = 1;  // (1 + rho) / (1 - rho) of the candidate's held-out residual
  int dof = 1;
  bool significant = false;
};
// loss_*: per-sample loss on all samples (sample_loss); rho_cand: the lag-1
// autocorrelation of the candidate's held-out residual; channels: squared
// residuals per sample
HeldOutTest held_out_test(const std::vector<double>& loss_ref, const std::vector<double>& loss_cand, double rho_cand,
                          const BlockSplit& s, int channels, int comparisons, int dof);

// The screen of a candidate's fit (effect_search.cpp): the first start of
// its fit must reach, within kScreenSets times BOBYQA's interpolation set
// (2n + 1 model runs for n parameters), a training loss whose profile
// statistic against the reference is the chi-square point at kScreenLevel
// (the median: 0.45 for one parameter), or it stops there and the candidate
// is not fitted in full (its second start is not run). An effect the data
// hold gains far more than that in its first steps, even where the reference
// has bent its base to absorb part of it (the base moves with it); a
// parameter that only fits noise stays at its null (LR 0) about half the
// time. A candidate that passes the screen gets the same fit as without it.
// A form that refines another (one more parameter) starts from that form's
// solution and is screened against it: the statistic of its extra parameter.
constexpr double kScreenLevel = 0.5;
constexpr int kScreenSets = 2;
double screen_crit(int dof);

// -2 x the Gaussian log-likelihood ratio of two models (reference minus
// candidate) from their summed losses in noise units over `terms` squared
// residuals, each model's variance profiled: max(1, sse / terms)
double profiled_lr(double sse_ref, double sse_cand, double terms);
// its inverse in the candidate: the summed loss at which profiled_lr is lr
// (0 where even a perfect fit would not reach it)
double profiled_sse_at(double sse_ref, double lr, double terms);

}  // namespace chainsim
