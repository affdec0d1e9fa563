// The calibration's acceptance tests (selection_rule.h).
#include "analysis/calibration/selection_rule.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace chainsim {

double normal_upper_quantile(double p) {
  // bisection on the upper tail 0.5 erfc(z / sqrt 2), monotone in z
  double lo = -40, hi = 40;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double student_t_upper_quantile(double p, int dof) {
  // Cornish-Fisher expansion of t in the normal quantile (Abramowitz and
  // Stegun 26.7.5): within 0.5 % for dof >= 10 at these tails
  const double z = normal_upper_quantile(p), v = std::max(1, dof);
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  return z + (z3 + z) / (4 * v) + (5 * z5 + 16 * z3 + 3 * z) / (96 * v * v) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * v * v * v);
}

double chi_square_95(int dof) {
  static const double q[] = {3.841, 5.991, 7.815, 9.488, 11.070, 12.592, 14.067, 15.507};
  return q[std::clamp(dof, 1, 8) - 1];
}

namespace {

// -2 log L = sse / v + terms log v, minimised over v >= 1 (the white noise):
// sse up to `terms`, then terms (1 + log(sse / terms)); increasing in sse
double m2ll(double sse, double terms) {
  const double v = std::max(1.0, sse / terms);
  return sse / v + terms * std::log(v);
}

}  // namespace

double profiled_lr(double sse_ref, double sse_cand, double terms) {
  if (terms <= 0) return 0.0;
  return m2ll(sse_ref, terms) - m2ll(sse_cand, terms);
}

double profiled_sse_at(double sse_ref, double lr, double terms) {
  if (terms <= 0) return 0.0;
  const double target = m2ll(sse_ref, terms) - lr;   // m2ll of the candidate
  if (target <= terms) return std::max(0.0, target);
  return terms * std::exp(target / terms - 1.0);
}

ProfileTest profile_test(double sse_ref, double sse_cand, double terms, double rho_cand, int dof) {
  ProfileTest t;
  t.dof = dof;
  t.inflation = (1 + rho_cand) / (1 - rho_cand);
  t.stat = profiled_lr(sse_ref, sse_cand, terms) / t.inflation;
  t.crit = chi_square_95(dof);
  t.excludes_null = t.stat >= t.crit;
  return t;
}

double chi_square_upper_quantile(double p, int dof) {
  const double z = normal_upper_quantile(p), k = std::max(1, dof), a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z * std::sqrt(a);
  return k * c * c * c;
}

double screen_crit(int dof) { return chi_square_upper_quantile(kScreenLevel, dof); }

HeldOutTest held_out_test(const std::vector<double>& loss_ref, const std::vector<double>& loss_cand, double rho_cand,
                          const BlockSplit& s, int channels, int comparisons, int dof) {
  HeldOutTest t;
  t.dof = dof;
  double sse_ref = 0, sse_cand = 0;
  size_t n = 0;
  for (size_t k = 0; k < loss_ref.size(); ++k) {
    if (!s.in(k, Samples::held_out)) continue;
    sse_ref += loss_ref[k];
    sse_cand += loss_cand[k];
    ++n;
  }
  const double rho = std::clamp(rho_cand, 0.0, 0.999);
  t.inflation = (1 + rho) / (1 - rho);
  t.crit = chi_square_upper_quantile(kTestLevel / std::max(1, comparisons), dof);
  if (n == 0) return t;
  t.gain = (sse_ref - sse_cand) / n;
  t.stat = profiled_lr(sse_ref, sse_cand, static_cast<double>(n) * std::max(1, channels)) / t.inflation;
  t.significant = t.stat >= t.crit;
  return t;
}

}  // namespace chainsim
