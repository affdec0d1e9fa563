// Statistics of a calibration residual (residual_stats.h).
#include "analysis/calibration/residual_stats.h"

#include <algorithm>
#include <cmath>

namespace chainsim {

BlockSplit split_blocks(const std::vector<double>& t, int blocks) {
  BlockSplit s;
  s.block.resize(t.size());
  s.batch.resize(t.size());
  const double t0 = t.front(), span = t.back() - t0;
  for (size_t k = 0; k < t.size(); ++k) {
    const double f = (t[k] - t0) / span * blocks;
    s.block[k] = std::min(blocks - 1, static_cast<int>(f));
    s.batch[k] = std::clamp(static_cast<int>((f - s.block[k]) * kBatchesPerBlock), 0, kBatchesPerBlock - 1);
  }
  return s;
}

namespace {

// per channel of r on `set`: the mean square and its white part (half the
// mean square of first differences within blocks; 0 without a pair), and
// the samples and pairs they were taken over
struct ChannelMs {
  double ms[2] = {0, 0}, white[2] = {0, 0};
  size_t n[2] = {0, 0}, pairs[2] = {0, 0};
};

ChannelMs channel_ms(const Residual& r, const BlockSplit& s, Samples set) {
  ChannelMs c;
  for (int ch = 0; ch < r.channels(); ++ch) {
    const std::vector<double>& v = ch == 0 ? r.angle : r.current;
    double s2 = 0, d2 = 0;
    size_t n = 0, nd = 0;
    for (size_t k = 0; k < v.size(); ++k) {
      if (!s.in(k, set)) continue;
      s2 += v[k] * v[k], ++n;
      if (k > 0 && s.block[k - 1] == s.block[k]) d2 += (v[k] - v[k - 1]) * (v[k] - v[k - 1]), ++nd;
    }
    c.ms[ch] = n ? s2 / n : 0.0;
    c.white[ch] = nd ? d2 / nd / 2.0 : 0.0;
    c.n[ch] = n, c.pairs[ch] = nd;
  }
  return c;
}

// the gap of a residual with mean squares c against the white parts `white`
double gap_of(const Residual& r, const ChannelMs& c, const double* white) {
  if (!r.finite) return 1e6;
  double tot = 0;
  for (int ch = 0; ch < r.channels(); ++ch) tot += std::max(0.0, c.ms[ch] - white[ch]);
  return std::sqrt(tot / r.channels());
}

}  // namespace

NoiseScale white_noise_scale(const Residual& r, const BlockSplit& s) {
  NoiseScale n;
  const ChannelMs c = channel_ms(r, s, Samples::all);
  for (int ch = 0; ch < r.channels(); ++ch) {
    const double sd = c.pairs[ch] ? std::sqrt(c.white[ch]) : 1.0;
    (ch == 0 ? n.angle : n.current) = std::max(sd, 1e-9);
  }
  return n;
}

std::vector<double> sample_loss(const Residual& r, const NoiseScale& n) {
  std::vector<double> out(r.size());
  for (size_t k = 0; k < r.size(); ++k) {
    const double a = r.angle[k] / n.angle, i = r.has_current ? r.current[k] / n.current : 0.0;
    out[k] = r.finite ? a * a + i * i : 1e12;
  }
  return out;
}

double residual_rho(const Residual& r, const NoiseScale& n, const BlockSplit& s, Samples set) {
  double c0 = 0, c1 = 0;
  for (int ch = 0; ch < r.channels(); ++ch) {
    const std::vector<double>& v = ch == 0 ? r.angle : r.current;
    const double sc = ch == 0 ? n.angle : n.current;
    for (size_t k = 0; k < v.size(); ++k) {
      if (!s.in(k, set)) continue;
      c0 += (v[k] / sc) * (v[k] / sc);
      if (k + 1 < v.size() && s.block[k + 1] == s.block[k]) c1 += (v[k] / sc) * (v[k + 1] / sc);
    }
  }
  return c0 > 0 ? std::clamp(c1 / c0, 0.0, 0.999) : 0.0;
}

double stdev(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double x : v) m += x;
  m /= v.size();
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / v.size());
}

double nrmse(const Residual& r, const BlockSplit& s, Samples set, const std::vector<bool>* mask) {
  if (!r.finite) return 1e6;
  double sa = 0, si = 0;
  size_t n = 0;
  for (size_t k = 0; k < r.size(); ++k) {
    if (!s.in(k, set) || (mask && !(*mask)[k])) continue;
    sa += r.angle[k] * r.angle[k];
    si += r.current[k] * r.current[k];
    ++n;
  }
  if (n == 0) return 0.0;
  return std::sqrt((sa + (r.has_current ? si : 0.0)) / n / (r.has_current ? 2.0 : 1.0));
}

double whiteness(const Residual& r, const BlockSplit& s, Samples set) {
  double worst = 0;
  const ChannelMs c = channel_ms(r, s, set);
  for (int ch = 0; ch < r.channels(); ++ch) {
    if (c.n[ch] == 0) continue;
    const double rms = std::sqrt(c.ms[ch]), rd = c.pairs[ch] ? std::sqrt(c.white[ch]) : 0.0;
    worst = std::max(worst, rd > 0 ? rms / rd : 1e3);
  }
  return worst;
}

double structured_error(const Residual& r, const BlockSplit& s, Samples set) {
  const ChannelMs c = channel_ms(r, s, set);
  return gap_of(r, c, c.white);
}

std::pair<double, double> structured_errors(const Residual& a, const Residual& b, const BlockSplit& s,
                                            Samples set) {
  const ChannelMs ca = channel_ms(a, s, set), cb = channel_ms(b, s, set);
  // a non-finite residual's differences say nothing about the noise
  double white[2];
  for (int ch = 0; ch < 2; ++ch)
    white[ch] = !a.finite ? cb.white[ch] : !b.finite ? ca.white[ch] : std::min(ca.white[ch], cb.white[ch]);
  return {gap_of(a, ca, white), gap_of(b, cb, white)};
}

std::vector<std::pair<double, double>> confidence_intervals(const Eigen::MatrixXd& J, const Eigen::VectorXd& r,
                                                            size_t samples, const std::vector<double>& x,
                                                            size_t first_nonnegative) {
  const size_t n = x.size(), m = samples;
  const double dof = std::max<double>(1.0, static_cast<double>(r.size()) - n);
  const double s2 = r.squaredNorm() / dof;
  // correlation length from the lag-1 autocorrelation of the angle residual
  double c0 = 0, c1 = 0;
  for (size_t k = 0; k + 1 < m; ++k) c0 += r(k) * r(k), c1 += r(k) * r(k + 1);
  const double rho = c0 > 0 ? std::clamp(c1 / c0, 0.0, 0.999) : 0.0;
  const double inflate = (1 + rho) / (1 - rho);
  Eigen::MatrixXd JtJ = J.transpose() * J;
  JtJ += 1e-12 * Eigen::MatrixXd::Identity(n, n) * std::max(1.0, JtJ.trace() / n);
  const Eigen::MatrixXd cov = JtJ.inverse() * s2 * inflate;
  std::vector<std::pair<double, double>> out(n);
  for (size_t i = 0; i < n; ++i) {
    const double sd = std::sqrt(std::max(0.0, cov(i, i)));
    double a = x[i] - 1.96 * sd, b = x[i] + 1.96 * sd;
    if (i >= first_nonnegative) a = std::max(a, 0.0);
    out[i] = {a, b};
  }
  return out;
}

}  // namespace chainsim
