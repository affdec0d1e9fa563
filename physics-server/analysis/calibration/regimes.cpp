// Regimes of a servo measurement (regimes.h).
#include "analysis/calibration/regimes.h"

#include <algorithm>
#include <cmath>

namespace chainsim {

const std::vector<std::string>& regime_names() {
  static const std::vector<std::string> names = {"step_onset", "reversal", "high_current",
                                                 "braking",    "slewing",  "hold"};
  return names;
}

std::vector<int> classify_regimes(const MeasuredRecord& m, double stall_current_a) {
  const size_t n = m.t.size();
  std::vector<int> reg(n, kHold);
  // measured speed, deg/s, over +-5 ms
  std::vector<double> w(n, 0.0);
  for (size_t k = 0; k < n; ++k) {
    size_t a = k, b = k;
    while (a > 0 && m.t[k] - m.t[a - 1] <= 0.005) --a;
    while (b + 1 < n && m.t[b + 1] - m.t[k] <= 0.005) ++b;
    if (b > a) w[k] = (m.angle[b] - m.angle[a]) / (m.t[b] - m.t[a]);
  }
  double last_change_t = -1e9, last_dir = 0;
  bool reversal = false;
  for (size_t k = 0; k < n; ++k) {
    if (k > 0 && std::fabs(m.sp[k] - m.sp[k - 1]) > 0.25) {
      const double dir = m.sp[k] > m.sp[k - 1] ? 1 : -1;
      reversal = last_dir != 0 && dir != last_dir;
      last_dir = dir;
      last_change_t = m.t[k];
    }
    const double err = m.sp[k] - m.angle[k];
    int r;
    if (m.t[k] - last_change_t < 0.04) r = reversal ? kReversal : kStepOnset;
    else if (m.has_current && m.current[k] > 0.6 * stall_current_a) r = kHighCurrent;
    else if (std::fabs(w[k]) > 20.0 && std::fabs(err) < 20.0) r = kBraking;
    else if (std::fabs(w[k]) > 20.0) r = kSlewing;
    else r = kHold;
    reg[k] = r;
  }
  return reg;
}

double regime_signature(const Residual& r, const std::vector<int>& regime, const std::vector<std::string>& names) {
  double e_in = 0, e_all = 0;
  size_t n_in = 0;
  for (size_t k = 0; k < regime.size(); ++k) {
    const bool in = std::find(names.begin(), names.end(), regime_names()[regime[k]]) != names.end();
    e_all += r.energy(k);
    if (in) e_in += r.energy(k), ++n_in;
  }
  if (e_all <= 0 || n_in == 0) return 0;
  return (e_in / e_all) / (static_cast<double>(n_in) / regime.size());
}

std::vector<RegimeRun> regime_runs(const std::vector<int>& regime) {
  std::vector<RegimeRun> out;
  const size_t n = regime.size();
  for (size_t a = 0; a < n;) {
    size_t b = a;
    while (b + 1 < n && regime[b + 1] == regime[a]) ++b;
    out.push_back({a, b, regime[a]});
    a = b + 1;
  }
  return out;
}

}  // namespace chainsim
