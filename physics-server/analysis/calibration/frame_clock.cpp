// The pwm frame clock of a measurement (frame_clock.h).
#include "analysis/calibration/frame_clock.h"

#include <algorithm>
#include <cmath>

#include "analysis/calibration/paired_runs.h"

namespace chainsim {
namespace {

constexpr double kGrid_s = 1e-4;     // the delay grid and the model's output grid
constexpr double kWindow_s = 0.3;    // a change's response window (at most)

// how far a measured delay is from the clock's predicted one (in [0,
// period)): directly, or across one frame edge (a change right at a frame
// can land on either side of it); a delay longer than the period plus the
// tolerance is never explained, so a clock of a fraction of the true period
// (whose predictions match the delays modulo its period) does not fit
double delay_dist(double pred, double delay, double period, double tol) {
  if (delay > period + tol) return 1e300;
  return std::min({std::fabs(pred - delay), std::fabs(pred + period - delay), std::fabs(pred - period - delay)});
}

}  // namespace

std::vector<SetpointChange> setpoint_changes(const MeasuredRecord& m) {
  std::vector<SetpointChange> out;
  for (size_t k = 1; k < m.size(); ++k)
    if (std::fabs(m.sp[k] - m.sp[k - 1]) > 0.25) out.push_back({k, m.t[k]});
  return out;
}

std::vector<ChangeDelay> estimate_delays(ModelRuns& runs, const FitProblem& p, const BenchConfig& b,
                                         double max_delay_s) {
  const MeasuredRecord& m = p.m;
  const double t0 = m.t.front();
  // the model on a uniform grid (the set-points act from the first step at
  // or after their time either way)
  const size_t ng = static_cast<size_t>(std::floor((m.t.back() - t0) / kGrid_s)) + 1;
  std::vector<double> tg(ng), spg(ng);
  for (size_t j = 0, k = 0; j < ng; ++j) {
    tg[j] = t0 + j * kGrid_s;
    while (k + 1 < m.size() && m.t[k + 1] <= tg[j] + 1e-12) ++k;
    spg[j] = m.sp[k];
  }
  const std::vector<BenchSample> sim = runs.simulate(b, tg, spg, SIZE_MAX);
  auto at = [&](double t, bool current) {
    const double f = std::clamp((t - t0) / kGrid_s, 0.0, static_cast<double>(ng - 1));
    const size_t j = std::min(static_cast<size_t>(f), ng - 2);
    const double w = f - j;
    return current ? (1 - w) * sim[j].current_a + w * sim[j + 1].current_a
                   : (1 - w) * sim[j].angle_deg + w * sim[j + 1].angle_deg;
  };
  const double wa = 1.0 / (p.sa * p.noise.angle), wi = 1.0 / (p.si * p.noise.current);
  const std::vector<SetpointChange> ch = setpoint_changes(m);
  const int nd = static_cast<int>(std::lround(max_delay_s / kGrid_s));
  std::vector<ChangeDelay> out;
  for (size_t c = 0; c < ch.size(); ++c) {
    const double tc = ch[c].t;
    const double t_end = std::min(tc + kWindow_s, c + 1 < ch.size() ? ch[c + 1].t : m.t.back() + 1);
    std::vector<double> e(nd + 1, 0.0);
    double terms = 0;   // residuals summed in each e[i]
    for (int i = 0; i <= nd; ++i) {
      const double delay = i * kGrid_s;
      for (size_t k = ch[c].k; k < m.size() && m.t[k] < t_end; ++k) {
        // delayed: until tc + delay the servo still does what it did at tc
        const double ts = std::max(m.t[k] - delay, tc);
        const double ra = wa * (at(ts, false) - m.angle[k]);
        const double ri = m.has_current ? wi * (at(ts, true) - m.current[k]) : 0.0;
        e[i] += ra * ra + ri * ri;
        if (i == 0) terms += m.has_current ? 2 : 1;
      }
    }
    const int best = static_cast<int>(std::min_element(e.begin(), e.end()) - e.begin());
    // curvature over +-1 ms: e ~ e_min + (delay - d)^2 / sd^2
    const int s = std::max(1, static_cast<int>(std::lround(1e-3 / kGrid_s)));
    const int lo = std::max(0, best - s), hi = std::min(nd, best + s);
    ChangeDelay d{tc, best * kGrid_s, -1, m.sp[ch[c].k] - m.sp[ch[c].k - 1], m.sp[ch[c].k]};
    if (hi > lo && best > 0 && best < nd) {
      const double hl = (best - lo) * kGrid_s, hh = (hi - best) * kGrid_s;
      const double c2 = 2 * ((e[lo] - e[best]) / hl + (e[hi] - e[best]) / hh) / (hl + hh);
      if (c2 > 0) d.sd = std::max(kGrid_s, std::sqrt(2.0 / c2));
    } else if (best == 0 && hi > 0) {   // at the edge: the one-sided rise
      const double rise = e[hi] - e[0];
      if (rise > 0) d.sd = std::max(kGrid_s, hi * kGrid_s / std::sqrt(rise));
    }
    // the curvature's sd holds where the model fits the change to the noise;
    // where it does not (an effect the model lacks), the misfit per residual
    // widens it
    if (d.sd > 0 && terms > 0) d.sd *= std::sqrt(std::max(1.0, e[best] / terms));
    out.push_back(d);
  }
  return out;
}

double frame_delay(const FrameClock& c, double t0, double t) {
  const double x = fmod_exact(c.phase_s - (t - t0), c.period_s);
  return x < 0 ? x + c.period_s : x;
}

FrameClockFit fit_frame_clock(const std::vector<ChangeDelay>& all, double t0, double period_lo, double period_hi,
                              double min_step_deg) {
  FrameClockFit out;
  // the changes (of min_step_deg or more) that tell their delay within 2 ms
  std::vector<ChangeDelay> d;
  for (const ChangeDelay& c : all)
    if (c.sd > 0 && c.sd < 2e-3 && std::fabs(c.step_deg) >= min_step_deg) d.push_back(c);
  out.used = static_cast<int>(d.size());
  if (d.size() < 4) return out;
  std::vector<double> tol(d.size());
  for (size_t c = 0; c < d.size(); ++c) tol[c] = std::max(5e-4, 2.5 * d[c].sd);
  // the clock's score; below `floor` it stops early and gives -1: each
  // change adds at most 1, so a clock whose score plus the changes left
  // cannot reach the floor is not scored further (the scan asks for the
  // best so far, less a margin far above the sum's rounding: it picks the
  // same clock as a full scoring would)
  // (f: the clock's frequency, 1 / period or near it. A distance below the
  // tolerance is the one whose ratio to it is below 1: the division is made
  // for those only)
  auto score = [&](double period, double f, double frame_abs, double floor) {
    double s = 0;
    for (size_t c = 0; c < d.size(); ++c) {
      if (s + static_cast<double>(d.size() - c) < floor) return -1.0;
      const double pred = wrap_to_period(frame_abs - d[c].t, period, f);
      const double dist = delay_dist(pred, d[c].delay, period, tol[c]);
      if (dist < tol[c]) {
        const double q = dist / tol[c];
        s += 1 - q * q;
      }
    }
    return s;
  };
  // anchors: the best-determined changes; each one's frame time sets the phase
  std::vector<size_t> order(d.size());
  for (size_t c = 0; c < d.size(); ++c) order[c] = c;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return d[a].sd < d[b].sd; });
  order.resize(std::min<size_t>(6, order.size()));
  const double span = std::max(0.1, d.back().t - d.front().t);
  const double df = 0.04 / span;
  double best = -1, best_period = 0, best_frame = 0;
  for (double f = 1.0 / period_hi; f <= 1.0 / period_lo + 1e-12; f += df)
    for (size_t a : order) {
      const double s = score(1.0 / f, f, d[a].t + d[a].delay, best + 1e-9 - 1e-6);
      if (s > best + 1e-9) best = s, best_period = 1.0 / f, best_frame = d[a].t + d[a].delay;
    }
  // weighted least squares of the inliers' frame times on their frame numbers
  double period = best_period, frame = best_frame;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  int inliers = 0;
  bool solved = false;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    std::vector<std::pair<double, double>> pts;   // (n, frame time), weight
    std::vector<double> wts;
    int inl = 0;
    for (size_t c = 0; c < d.size(); ++c) {
      const double pred = wrap_to_period(frame - d[c].t, period);
      if (delay_dist(pred, d[c].delay, period, tol[c]) >= tol[c]) continue;
      ++inl;
      // a delay within 2 sd of 0 is censored (it cannot come out negative):
      // an inlier, but biased, so it stays out of the least squares
      if (d[c].delay + d[c].shift < 2 * d[c].sd) continue;
      const double fc = d[c].t + d[c].delay;
      const double n = std::round((fc - frame) / period);
      const double w = 1.0 / (d[c].sd * d[c].sd);
      A(0, 0) += w, A(0, 1) += w * n, A(1, 1) += w * n * n;
      rhs(0) += w * fc, rhs(1) += w * n * fc;
      pts.push_back({n, fc});
      wts.push_back(w);
    }
    A(1, 0) = A(0, 1);
    inliers = inl;
    if (pts.size() < 3 || std::fabs(A.determinant()) < 1e-30) break;
    const Eigen::Vector2d sol = A.ldlt().solve(rhs);   // frame time at n = 0, period
    double chi2 = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      const double r = pts[i].second - sol(0) - sol(1) * pts[i].first;
      chi2 += wts[i] * r * r;
    }
    frame = sol(0), period = sol(1);
    solved = true;
    cov = A.inverse() * std::max(1.0, chi2 / std::max<int>(1, static_cast<int>(pts.size()) - 2));
  }
  out.inliers = inliers;
  // the range with 1 % slack: a clock at the range's end fits a hair beyond it
  if (!solved || inliers < 4 || 2 * inliers < out.used || !(period >= 0.99 * period_lo && period <= 1.01 * period_hi))
    return out;
  // the phase: the first frame at or after t0, t0 + phase = frame + m period
  const double m = std::ceil((t0 - frame) / period - 1e-12);
  out.clock.period_s = period;
  out.clock.phase_s = std::clamp(frame + m * period - t0, 0.0, period);
  const double sd_t = std::sqrt(std::max(0.0, cov(1, 1)));
  const double sd_p = std::sqrt(std::max(0.0, cov(0, 0) + m * m * cov(1, 1) + 2 * m * cov(0, 1)));
  out.period_ci_s = {period - 1.96 * sd_t, period + 1.96 * sd_t};
  out.phase_ci_s = {out.clock.phase_s - 1.96 * sd_p, out.clock.phase_s + 1.96 * sd_p};
  out.found = true;
  return out;
}

bool same_frames(const FrameClock& a, const FrameClock& b, double span_s, double tol_s) {
  if (!(a.period_s > 0.0) || !(b.period_s > 0.0)) return false;
  // b's first frame against a's nearest one, then the drift over the span
  const double d0 = std::remainder(b.phase_s - a.phase_s, a.period_s);
  const double frames = span_s / a.period_s;
  const double d1 = d0 + frames * (b.period_s - a.period_s);
  return std::fabs(d0) <= tol_s && std::fabs(d1) <= tol_s;
}

namespace {

// the catalogue's period range, s
std::pair<double, double> period_range() {
  double lo = 2.5e-3, hi = 40e-3;
  for (const Effect& e : effect_catalogue())
    if (e.fit == EffectFit::frame_clock) lo = e.params[0].lo * e.params[0].to_model, hi = e.params[0].hi * e.params[0].to_model;
  return {lo, hi};
}

}  // namespace

FrameClockFit frame_clock_for(ModelRuns& runs, const FitProblem& p, const BenchConfig& b) {
  const auto [lo, hi] = period_range();
  return fit_frame_clock(estimate_delays(runs, p, b, hi), p.m.t.front(), lo, hi);
}

namespace {

// the clocks of delays d: from every change, and from the large steps where
// their frames differ
std::vector<FrameClockFit> clocks_of(const FitProblem& p, const std::vector<ChangeDelay>& d) {
  const auto [lo, hi] = period_range();
  std::vector<FrameClockFit> out;
  const FrameClockFit all = fit_frame_clock(d, p.m.t.front(), lo, hi);
  if (all.found) out.push_back(all);
  const FrameClockFit large = fit_frame_clock(d, p.m.t.front(), lo, hi, kClockMinStepDeg);
  // (a second clock within the fit's phase window of the first would be
  // fitted to the same solution: a thousand model runs for nothing)
  const double span = p.m.t.back() - p.m.t.front();
  if (large.found && !(all.found && same_frames(all.clock, large.clock, span, 1e-3 * kClockPhaseWindowMs)))
    out.push_back(large);
  return out;
}

}  // namespace

std::vector<FrameClockFit> frame_clocks_for(ModelRuns& runs, const FitProblem& p, const BenchConfig& b) {
  return clocks_of(p, estimate_delays(runs, p, b, period_range().second));
}

std::vector<ChangeDelay> falling_edge_delays(const std::vector<ChangeDelay>& d, double k_s_per_deg) {
  std::vector<ChangeDelay> out = d;
  for (ChangeDelay& c : out) {
    const double s = rc_pulse_width_s(k_s_per_deg, c.sp_deg);
    c.delay -= s;
    c.shift += s;
  }
  return out;
}

std::vector<PulseClock> pulse_clocks_for(ModelRuns& runs, const FitProblem& p, const BenchConfig& b,
                                         const std::vector<double>& slopes_us_per_deg) {
  const std::vector<ChangeDelay> d = estimate_delays(runs, p, b, period_range().second);
  std::vector<PulseClock> all;
  for (double k : slopes_us_per_deg)
    for (const FrameClockFit& fc : clocks_of(p, falling_edge_delays(d, 1e-6 * k))) all.push_back({k, fc});
  std::stable_sort(all.begin(), all.end(),
                   [](const PulseClock& a, const PulseClock& b) { return a.fit.inliers > b.fit.inliers; });
  const double span = p.m.t.back() - p.m.t.front();
  std::vector<PulseClock> out;
  for (const PulseClock& c : all)
    if (std::none_of(out.begin(), out.end(), [&](const PulseClock& o) {
          return same_frames(o.fit.clock, c.fit.clock, span, 1e-3 * kClockPhaseWindowMs);
        }))
      out.push_back(c);
  return out;
}

}  // namespace chainsim
