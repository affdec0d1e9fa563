// `chainsim calibrate`: see calibrate_command.h and docs/calibration.md.
//
// Method, in short:
//  1. the measurement is cut into kBlocks time blocks; even blocks train, odd
//     blocks are held out (block cross-validation of a time series);
//  2. the base parameters (Kp, Km = Kt scale, R, load inertia) are refitted on
//     the training blocks (NLopt BOBYQA, derivative-free: several effects are
//     not smooth in their parameter); gap_before = held-out error;
//  3. the disagreement is localised: each sample gets a regime (step onset,
//     reversal, high current, braking, slewing, hold), contiguous runs are
//     regions, and the residual is summarised per regime;
//  4. while the held-out residual is structured (not consistent with white
//     noise), every catalogue effect not yet added is fitted together with the
//     base parameters on the training blocks (its parameter started from the
//     best of a small grid); candidates are ranked by held-out error, the
//     residual signature (share of the residual in the regimes the effect acts
//     in) is reported with them; the best is accepted only when it cuts the
//     held-out error by at least kMinGain; greedy;
//  5. verdict: residual consistent with noise -> explained (or
//     no_missing_effect when nothing was added); otherwise unexplained;
//  6. the final model is refitted on all data for the reported parameters and
//     their 95 % intervals (Gauss-Newton covariance from a finite-difference
//     Jacobian, inflated by the residual's correlation length).
#include "chainsim/calibrate_command.h"

#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <nlopt.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "chainsim/bench_command.h"
#include "chainsim/robot_calibration.h"
#include "physics/actuators/servo_model.h"

namespace chainsim {
namespace {

constexpr int kBlocks = 8;           // time blocks; even = training, odd = held out
constexpr double kMinGain = 0.30;    // an effect must cut the held-out structured error by 30 %
constexpr double kWhiteMax = 1.6;    // whiteness ratio below which a residual is noise
constexpr int kMaxEvalBase = 250;
constexpr int kMaxEvalJoint = 400;

struct CalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// ---------------------------------------------------------------- measured CSV

struct Measured {
  std::vector<double> t, sp, angle, current;
  bool has_current = false;
};

std::string trim(const std::string& s, size_t* lead = nullptr) {
  size_t a = 0, b = s.size();
  while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
  while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
  if (lead) *lead = a;
  return s.substr(a, b - a);
}

struct Cell {
  std::string text;
  int column = 1;
};

std::vector<Cell> split(const std::string& line) {
  std::vector<Cell> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    const std::string raw = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t lead = 0;
    Cell c;
    c.text = trim(raw, &lead);
    c.column = static_cast<int>(start + lead) + 1;
    out.push_back(c);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

Measured read_measured(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw CalError(file + ": cannot open the measurement file");
  auto fail = [&](int line, int col, const std::string& what) {
    return CalError(file + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + what);
  };
  Measured m;
  std::string line;
  int lineno = 0;
  int cols[4] = {-1, -1, -1, -1};
  const char* names[4] = {"t_s", "setpoint_deg", "angle_deg", "current_a"};
  std::vector<double>* dst[4] = {&m.t, &m.sp, &m.angle, &m.current};
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (lineno == 1) {
      std::set<std::string> seen;
      std::string have;
      const std::vector<Cell> cells = split(line);
      for (size_t k = 0; k < cells.size(); ++k) {
        std::string n = cells[k].text;
        if (n.size() >= 2 && n.front() == '"' && n.back() == '"') n = n.substr(1, n.size() - 2);
        if (!n.empty() && !seen.insert(n).second)
          throw fail(1, cells[k].column, "column '" + n + "' appears twice in the header");
        have += (have.empty() ? "" : ", ") + n;
        for (int c = 0; c < 4; ++c)
          if (n == names[c]) cols[c] = static_cast<int>(k);
      }
      for (int c = 0; c < 3; ++c)
        if (cols[c] < 0)
          throw fail(1, 1, std::string("missing column '") + names[c] + "' in the header (the header has: " +
                               have + "; needed: t_s, setpoint_deg, angle_deg; optional: current_a)");
      m.has_current = cols[3] >= 0;
      continue;
    }
    if (trim(line).empty()) continue;
    const std::vector<Cell> cells = split(line);
    for (int c = 0; c < 4; ++c) {
      if (cols[c] < 0) continue;
      if (cols[c] >= static_cast<int>(cells.size()))
        throw fail(lineno, static_cast<int>(line.size()) + 1,
                   std::string("missing column '") + names[c] + "' (this row has " +
                       std::to_string(cells.size()) + " cells)");
      const Cell& cell = cells[cols[c]];
      if (cell.text.empty()) throw fail(lineno, cell.column, std::string("empty cell in column '") + names[c] + "'");
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(cell.text.c_str(), &end);
      if (end != cell.text.c_str() + cell.text.size())
        throw fail(lineno, cell.column, "'" + cell.text + "' in column '" + names[c] + "' is not a number");
      if (!std::isfinite(v))
        throw fail(lineno, cell.column, "'" + cell.text + "' in column '" + names[c] + "' is not a finite number");
      if (c == 0 && !m.t.empty() && !(v > m.t.back()))
        throw fail(lineno, cell.column, "t_s = " + cell.text + " is not after the previous row's: times must be strictly increasing");
      dst[c]->push_back(v);
    }
  }
  if (lineno == 0) throw fail(1, 1, "empty file: expected a header naming t_s, setpoint_deg, angle_deg");
  if (m.t.size() < 4 * kBlocks)
    throw fail(lineno, 1, "too few rows (" + std::to_string(m.t.size()) + "; at least " +
                              std::to_string(4 * kBlocks) + " needed for the cross-validation blocks)");
  return m;
}

// ---------------------------------------------------------------- the catalogue

struct Effect {
  const char* name;
  const char* param;       // its name in report.json
  double ServoParams::*member;
  double to_model;         // model value = param value * to_model
  double lo, hi;           // fit bounds (param units)
  std::vector<double> grid;
  std::vector<std::string> regimes;  // where its signature is expected
  bool discrete = false;   // chosen from the grid only (not refined continuously)
};

const std::vector<Effect>& catalogue() {
  static const std::vector<Effect> c = {
      {"static_friction_threshold", "i_threshold_a", &ServoParams::i_threshold_a, 1.0, 0.0, 0.2,
       {0.02, 0.05, 0.1}, {"hold", "step_onset"}},
      {"coulomb_friction", "torque_nm", &ServoParams::coulomb_nm, 1.0, 0.0, 0.03,
       {0.002, 0.005, 0.01}, {"braking", "hold"}},
      {"backlash", "width_deg", &ServoParams::backlash_deg, 1.0, 0.0, 10.0, {1.0, 2.5, 5.0},
       {"reversal", "braking"}},
      {"deadband", "width_deg", &ServoParams::deadband_deg, 1.0, 0.0, 10.0, {1.0, 2.5, 5.0},
       {"hold", "braking"}},
      {"supply_sag", "r_ohm", &ServoParams::supply_sag_ohm, 1.0, 0.0, 12.0, {1.0, 3.0, 6.0},
       {"high_current", "slewing"}},
      // the frame period is one of the usual servo frame rates (100, 60, 50,
      // 40, 30 Hz), not refined: the latch instants are piecewise constant in it
      {"pwm_frame_delay", "frame_ms", &ServoParams::pwm_frame_s, 1e-3, 0.0, 40.0,
       {10.0, 50.0 / 3, 20.0, 25.0, 100.0 / 3}, {"step_onset", "reversal"}, true},
      {"current_limit", "limit_a", &ServoParams::current_limit_a, 1.0, 0.03, 0.6, {0.1, 0.2, 0.3},
       {"high_current", "slewing"}},
  };
  return c;
}

// ---------------------------------------------------------------- model and error

const char* kBaseNames[] = {"Kp", "Km_Kt", "R", "load_inertia"};
constexpr int kNumBase = 4;

struct Problem {
  BenchConfig datasheet;
  Measured m;
  double sa = 1, si = 1;             // normalisation: std of measured angle / current
  std::vector<int> block;            // block of each sample
};

// x = base factors (kNumBase) then one value per effect in `effects`
BenchConfig make_config(const Problem& p, const std::vector<int>& effects, const std::vector<double>& x) {
  BenchConfig b = p.datasheet;
  b.servo.kp *= x[0];
  b.servo.km *= x[1];
  b.servo.kt *= x[1];
  b.servo.r *= x[2];
  b.load_inertia_kgm2 *= x[3];
  for (size_t e = 0; e < effects.size(); ++e) {
    const Effect& ef = catalogue()[effects[e]];
    b.servo.*(ef.member) = x[kNumBase + e] * ef.to_model;
  }
  return b;
}

struct Residual {
  std::vector<double> ra, ri;   // normalised residuals (sim - meas)/scale
  std::vector<BenchSample> sim;
  bool ok = true;
};

Residual residual(const Problem& p, const BenchConfig& b) {
  Residual r;
  r.sim = simulate_bench(b, p.m.t, p.m.sp, BenchSolver::closed_form);
  const size_t n = p.m.t.size();
  r.ra.resize(n);
  r.ri.assign(n, 0.0);
  for (size_t k = 0; k < n; ++k) {
    r.ra[k] = (r.sim[k].angle_deg - p.m.angle[k]) / p.sa;
    if (p.m.has_current) r.ri[k] = (r.sim[k].current_a - p.m.current[k]) / p.si;
    if (!std::isfinite(r.ra[k]) || !std::isfinite(r.ri[k])) r.ok = false;
  }
  return r;
}

// which samples count: 0 = training blocks, 1 = held-out blocks, 2 = all
bool in_set(const Problem& p, size_t k, int set) {
  return set == 2 || (p.block[k] % 2) == set;
}

// the metric: sqrt(mean over channels of the mean squared normalised residual)
double metric(const Problem& p, const Residual& r, int set, const std::vector<bool>* mask = nullptr) {
  if (!r.ok) return 1e6;
  double sa = 0, si = 0;
  size_t n = 0;
  for (size_t k = 0; k < r.ra.size(); ++k) {
    if (!in_set(p, k, set) || (mask && !(*mask)[k])) continue;
    sa += r.ra[k] * r.ra[k];
    si += r.ri[k] * r.ri[k];
    ++n;
  }
  if (n == 0) return 0.0;
  return std::sqrt((sa + (p.m.has_current ? si : 0.0)) / n / (p.m.has_current ? 2.0 : 1.0));
}

// whiteness ratio of the residual on `set`: rms / (rms of first differences / sqrt 2),
// within blocks; ~1 for white noise, >> 1 for a structured (slow) residual.
// The larger of the two channels.
double whiteness(const Problem& p, const Residual& r, int set) {
  double worst = 0;
  for (int ch = 0; ch < (p.m.has_current ? 2 : 1); ++ch) {
    const std::vector<double>& v = ch == 0 ? r.ra : r.ri;
    double s2 = 0, d2 = 0, mean = 0;
    size_t n = 0, nd = 0;
    for (size_t k = 0; k < v.size(); ++k)
      if (in_set(p, k, set)) mean += v[k], ++n;
    if (n == 0) continue;
    mean /= n;
    for (size_t k = 0; k < v.size(); ++k) {
      if (!in_set(p, k, set)) continue;
      s2 += v[k] * v[k];
      if (k > 0 && p.block[k - 1] == p.block[k]) d2 += (v[k] - v[k - 1]) * (v[k] - v[k - 1]), ++nd;
    }
    const double rms = std::sqrt(s2 / n), rd = nd ? std::sqrt(d2 / nd / 2.0) : 0.0;
    worst = std::max(worst, rd > 0 ? rms / rd : 1e3);
  }
  return worst;
}

// the structured part of the error on `set`: sqrt(max(0, MS - MS_white)),
// MS_white = mean square of first differences / 2 (within blocks), per channel,
// combined like metric(): the error left once the white measurement noise is
// taken out (0 for a model that explains the data down to the noise)
double structured(const Problem& p, const Residual& r, int set) {
  if (!r.ok) return 1e6;
  double tot = 0;
  const int nch = p.m.has_current ? 2 : 1;
  for (int ch = 0; ch < nch; ++ch) {
    const std::vector<double>& v = ch == 0 ? r.ra : r.ri;
    double s2 = 0, d2 = 0;
    size_t n = 0, nd = 0;
    for (size_t k = 0; k < v.size(); ++k) {
      if (!in_set(p, k, set)) continue;
      s2 += v[k] * v[k], ++n;
      if (k > 0 && p.block[k - 1] == p.block[k]) d2 += (v[k] - v[k - 1]) * (v[k] - v[k - 1]), ++nd;
    }
    if (n) tot += std::max(0.0, s2 / n - (nd ? d2 / nd / 2.0 : 0.0));
  }
  return std::sqrt(tot / nch);
}

struct Fit {
  std::vector<int> effects;
  std::vector<double> x;
  double train = 0, held = 0, white = 0, gap = 0;
  int evals = 0;
};

int g_evals = 0;

// least squares on `set` with NLopt BOBYQA, from x0, within the bounds
Fit fit(const Problem& p, const std::vector<int>& effects, std::vector<double> x0, int set, int max_eval) {
  const size_t n = x0.size();
  std::vector<double> lo(n), hi(n);
  for (int i = 0; i < kNumBase; ++i) lo[i] = 0.6, hi[i] = 1.6;
  for (size_t e = 0; e < effects.size(); ++e) {
    lo[kNumBase + e] = catalogue()[effects[e]].lo;
    hi[kNumBase + e] = catalogue()[effects[e]].hi;
    if (catalogue()[effects[e]].discrete) lo[kNumBase + e] = hi[kNumBase + e] = x0[kNumBase + e];
  }
  // scaled variables: u = (x - lo)/(hi - lo) in [0, 1]
  std::vector<double> u(n);
  for (size_t i = 0; i < n; ++i)
    u[i] = hi[i] > lo[i] ? std::clamp((x0[i] - lo[i]) / (hi[i] - lo[i]), 0.0, 1.0) : 0.0;
  struct Ctx {
    const Problem* p;
    const std::vector<int>* effects;
    const std::vector<double>*lo, *hi;
    int set;
    int evals = 0;
  } ctx{&p, &effects, &lo, &hi, set};
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_maxeval(max_eval);
  opt.set_xtol_abs(1e-5);
  opt.set_ftol_rel(1e-7);
  opt.set_initial_step(std::vector<double>(n, 0.08));
  opt.set_min_objective(
      [](unsigned nn, const double* uu, double*, void* data) -> double {
        Ctx& c = *static_cast<Ctx*>(data);
        std::vector<double> x(nn);
        for (unsigned i = 0; i < nn; ++i) x[i] = (*c.lo)[i] + uu[i] * ((*c.hi)[i] - (*c.lo)[i]);
        ++c.evals;
        const double m = metric(*c.p, residual(*c.p, make_config(*c.p, *c.effects, x)), c.set);
        return m * m;
      },
      &ctx);
  double f = 0;
  try {
    opt.optimize(u, f);
  } catch (const nlopt::roundoff_limited&) {
  } catch (const std::runtime_error&) {
  }
  Fit out;
  out.effects = effects;
  out.x.resize(n);
  for (size_t i = 0; i < n; ++i) out.x[i] = lo[i] + u[i] * (hi[i] - lo[i]);
  const Residual r = residual(p, make_config(p, effects, out.x));
  out.train = metric(p, r, set);
  out.held = metric(p, r, 1);
  out.white = whiteness(p, r, 1);
  out.gap = structured(p, r, 1);
  out.evals = ctx.evals;
  g_evals += ctx.evals;
  return out;
}

// fit with one more effect: its parameter from the best grid value (others
// held), then everything together. Two starts, the better training fit kept:
// the current model's base factors, and the datasheet's (1.0; the effects
// already accepted keep their values). The current base was refitted without
// the new effect, so it has absorbed what it could of it (a missing Coulomb
// friction pulls Km = Kt down, R up and the load inertia to its bound), and
// from there a local optimiser can stay in that compensated basin: the
// least-squares objective is multimodal, for the generator's own physics as
// much as for the model (docs/calibration.md, "Limits").
Fit fit_with(const Problem& p, const Fit& base, int effect) {
  std::vector<int> eff = base.effects;
  eff.push_back(effect);
  Fit best_fit;
  bool have = false;
  for (int start = 0; start < 2; ++start) {
    std::vector<double> x = base.x;
    if (start == 1) std::fill(x.begin(), x.begin() + kNumBase, 1.0);
    x.push_back(0.0);
    double best = 1e300, best_v = catalogue()[effect].grid[0];
    for (double v : catalogue()[effect].grid) {
      x.back() = v;
      const double m = metric(p, residual(p, make_config(p, eff, x)), 0);
      ++g_evals;
      if (m < best) best = m, best_v = v;
    }
    x.back() = best_v;
    Fit f = fit(p, eff, x, 0, kMaxEvalJoint);
    if (!have || f.train < best_fit.train) best_fit = std::move(f), have = true;
  }
  return best_fit;
}

// ---------------------------------------------------------------- regimes

const std::vector<std::string> kRegimes = {"step_onset", "reversal", "high_current", "braking", "slewing", "hold"};

std::vector<int> classify(const Problem& p) {
  const Measured& m = p.m;
  const size_t n = m.t.size();
  std::vector<int> reg(n, 5);
  // measured speed, deg/s, over +-5 ms
  std::vector<double> w(n, 0.0);
  for (size_t k = 0; k < n; ++k) {
    size_t a = k, b = k;
    while (a > 0 && m.t[k] - m.t[a - 1] <= 0.005) --a;
    while (b + 1 < n && m.t[b + 1] - m.t[k] <= 0.005) ++b;
    if (b > a) w[k] = (m.angle[b] - m.angle[a]) / (m.t[b] - m.t[a]);
  }
  const double stall = p.datasheet.servo.supply_v / p.datasheet.servo.r;
  double last_change_t = -1e9, last_dir = 0, change_dir = 0;
  bool reversal = false;
  for (size_t k = 0; k < n; ++k) {
    if (k > 0 && std::fabs(m.sp[k] - m.sp[k - 1]) > 0.25) {
      const double dir = m.sp[k] > m.sp[k - 1] ? 1 : -1;
      reversal = last_dir != 0 && dir != last_dir;
      last_dir = change_dir = dir;
      last_change_t = m.t[k];
    }
    const double err = m.sp[k] - m.angle[k];
    int r;
    if (m.t[k] - last_change_t < 0.04) r = reversal ? 1 : 0;
    else if (m.has_current && m.current[k] > 0.6 * stall) r = 2;
    else if (std::fabs(w[k]) > 20.0 && std::fabs(err) < 20.0) r = 3;
    else if (std::fabs(w[k]) > 20.0) r = 4;
    else r = 5;
    reg[k] = r;
  }
  (void)change_dir;
  return reg;
}

double sq(const Problem& p, const Residual& r, size_t k) {
  return r.ra[k] * r.ra[k] + (p.m.has_current ? r.ri[k] * r.ri[k] : 0.0);
}

// share of the residual energy in these regimes divided by their share of time
double signature(const Problem& p, const Residual& r, const std::vector<int>& reg,
                 const std::vector<std::string>& regimes) {
  double e_in = 0, e_all = 0;
  size_t n_in = 0;
  for (size_t k = 0; k < reg.size(); ++k) {
    const bool in = std::find(regimes.begin(), regimes.end(), kRegimes[reg[k]]) != regimes.end();
    e_all += sq(p, r, k);
    if (in) e_in += sq(p, r, k), ++n_in;
  }
  if (e_all <= 0 || n_in == 0) return 0;
  return (e_in / e_all) / (static_cast<double>(n_in) / reg.size());
}

// ---------------------------------------------------------------- CIs

// 95 % intervals of x from the residual Jacobian on all data; the covariance is
// inflated by the residual's correlation length (samples are not independent)
std::vector<std::pair<double, double>> intervals(const Problem& p, const Fit& f) {
  const size_t n = f.x.size();
  const Residual r0 = residual(p, make_config(p, f.effects, f.x));
  const size_t m = r0.ra.size();
  const int nch = p.m.has_current ? 2 : 1;
  Eigen::MatrixXd J(m * nch, n);
  Eigen::VectorXd r(m * nch);
  for (size_t k = 0; k < m; ++k) {
    r(k) = r0.ra[k];
    if (nch == 2) r(m + k) = r0.ri[k];
  }
  for (size_t i = 0; i < n; ++i) {
    double hstep;
    if (i < kNumBase) hstep = 0.01;
    else {
      const Effect& e = catalogue()[f.effects[i - kNumBase]];
      hstep = std::max(0.02 * std::fabs(f.x[i]), 0.002 * (e.hi - e.lo));
    }
    std::vector<double> xp = f.x, xm = f.x;
    xp[i] += hstep;
    xm[i] -= hstep;
    if (i >= kNumBase && xm[i] < 0) xm[i] = 0, xp[i] = 2 * hstep;  // stay at >= 0
    const Residual rp = residual(p, make_config(p, f.effects, xp));
    const Residual rm = residual(p, make_config(p, f.effects, xm));
    for (size_t k = 0; k < m; ++k) {
      J(k, i) = (rp.ra[k] - rm.ra[k]) / (xp[i] - xm[i]);
      if (nch == 2) J(m + k, i) = (rp.ri[k] - rm.ri[k]) / (xp[i] - xm[i]);
    }
  }
  const double dof = std::max<double>(1.0, static_cast<double>(m * nch) - n);
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
    double a = f.x[i] - 1.96 * sd, b = f.x[i] + 1.96 * sd;
    if (i >= kNumBase) a = std::max(a, 0.0);
    out[i] = {a, b};
  }
  return out;
}

// ---------------------------------------------------------------- plots

std::string fmt(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, std::fabs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

// a plain SVG line chart; series: (label, colour, y values); x = t
std::string svg_chart(const std::string& title, const std::string& ylabel, const std::vector<double>& t,
                      const std::vector<std::tuple<std::string, std::string, std::vector<double>>>& series) {
  const double W = 900, H = 260, L = 60, R = 150, T = 28, B = 34;
  double y0 = 1e300, y1 = -1e300;
  for (const auto& s : series)
    for (double v : std::get<2>(s)) y0 = std::min(y0, v), y1 = std::max(y1, v);
  if (!(y1 > y0)) y1 = y0 + 1;
  const double pad = 0.05 * (y1 - y0);
  y0 -= pad, y1 += pad;
  const double t0 = t.front(), t1 = t.back();
  auto X = [&](double x) { return L + (x - t0) / (t1 - t0) * (W - L - R); };
  auto Y = [&](double y) { return T + (y1 - y) / (y1 - y0) * (H - T - B); };
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='11'>\n<rect width='100%' height='100%' fill='white'/>\n";
  s << "<text x='" << L << "' y='16' font-size='13'>" << title << "</text>\n";
  s << "<rect x='" << L << "' y='" << T << "' width='" << (W - L - R) << "' height='" << (H - T - B)
    << "' fill='none' stroke='#888'/>\n";
  for (int i = 0; i <= 4; ++i) {
    const double yv = y0 + (y1 - y0) * i / 4, xv = t0 + (t1 - t0) * i / 4;
    s << "<text x='" << (L - 4) << "' y='" << Y(yv) + 4 << "' text-anchor='end'>" << fmt(yv, 3) << "</text>\n";
    s << "<text x='" << X(xv) << "' y='" << (H - B + 14) << "' text-anchor='middle'>" << fmt(xv, 3) << "</text>\n";
  }
  s << "<text x='" << (W - R) / 2 << "' y='" << (H - 4) << "'>t (s)</text>\n";
  s << "<text x='12' y='" << H / 2 << "' transform='rotate(-90 12 " << H / 2 << ")'>" << ylabel << "</text>\n";
  const size_t n = t.size(), stride = std::max<size_t>(1, n / 1500);
  int li = 0;
  for (const auto& [label, colour, y] : series) {
    s << "<polyline fill='none' stroke='" << colour << "' stroke-width='1' points='";
    for (size_t k = 0; k < n; k += stride) s << fmt(X(t[k]), 6) << "," << fmt(Y(y[k]), 6) << " ";
    s << "'/>\n";
    s << "<line x1='" << (W - R + 10) << "' x2='" << (W - R + 30) << "' y1='" << (T + 10 + 16 * li)
      << "' y2='" << (T + 10 + 16 * li) << "' stroke='" << colour << "' stroke-width='2'/>";
    s << "<text x='" << (W - R + 35) << "' y='" << (T + 14 + 16 * li) << "'>" << label << "</text>\n";
    ++li;
  }
  s << "</svg>\n";
  return s.str();
}

void write_file(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw CalError(path + ": cannot write");
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) throw CalError(path + ": cannot write");
}

// ---------------------------------------------------------------- the command

struct CalArgs {
  std::string bench, measured, out;
  bool quiet = false;
};

CalArgs g_args;
robotcal::RobotArgs g_robot;
int g_exit = -1;

struct Candidate {
  int effect;
  Fit fit;
  double sig;
  bool accepted = false;
  std::string why;
};

int run(const CalArgs& a) {
  const auto t_start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) {
    if (a.quiet) return;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    std::fprintf(stderr, "chainsim calibrate [%6.1f s] %s\n", el, s.c_str());
  };
  try {
    Problem p;
    p.datasheet = a.bench.empty() ? BenchConfig{} : load_bench_config(a.bench);
    // the fit uses a step of at most 100 us, so the scheme's own discretisation
    // error (0.09 degrees at 500 us, docs/servo-bench.md) stays below the noise
    p.datasheet.dt_us = std::min<int64_t>(p.datasheet.dt_us, 100);
    p.m = read_measured(a.measured);
    std::error_code ec;
    std::filesystem::create_directories(a.out, ec);
    if (!std::filesystem::is_directory(a.out)) throw CalError(a.out + ": cannot create the output directory");
    const size_t n = p.m.t.size();
    auto stdev = [](const std::vector<double>& v) {
      double m = 0, s = 0;
      for (double x : v) m += x;
      m /= v.size();
      for (double x : v) s += (x - m) * (x - m);
      return std::sqrt(s / v.size());
    };
    p.sa = std::max(stdev(p.m.angle), 1e-3);
    if (p.m.has_current) p.si = std::max(stdev(p.m.current), 1e-5);
    p.block.resize(n);
    const double t0 = p.m.t.front(), span = p.m.t.back() - t0;
    for (size_t k = 0; k < n; ++k)
      p.block[k] = std::min(kBlocks - 1, static_cast<int>((p.m.t[k] - t0) / span * kBlocks));
    const std::vector<int> reg = classify(p);
    say(std::to_string(n) + " samples, " + fmt(span) + " s; " + (p.m.has_current ? "angle and current" : "angle only") +
        "; " + std::to_string(kBlocks) + " blocks (even: fit, odd: held out)");

    // 1. base refit
    const std::vector<double> ones(kNumBase, 1.0);
    const Residual r_data = residual(p, p.datasheet);
    const double gap_datasheet = metric(p, r_data, 1);
    Fit cur = fit(p, {}, ones, 0, kMaxEvalBase);
    const Fit base = cur;
    say("datasheet model: held-out NRMSE " + fmt(gap_datasheet) + "; refitted base: " + fmt(cur.held) +
        ", structured " + fmt(cur.gap) +
        " (whiteness " + fmt(cur.white, 3) + ", " + std::to_string(cur.evals) + " evaluations)");

    // 2. greedy effects
    std::vector<std::vector<Candidate>> rounds;
    std::set<int> used;
    while (cur.white > kWhiteMax && used.size() < catalogue().size()) {
      const Residual rc = residual(p, make_config(p, cur.effects, cur.x));
      std::vector<Candidate> cands;
      for (int e = 0; e < static_cast<int>(catalogue().size()); ++e) {
        if (used.count(e)) continue;
        Candidate c{e, fit_with(p, cur, e), signature(p, rc, reg, catalogue()[e].regimes), false, {}};
        say("  candidate " + std::string(catalogue()[e].name) + " = " + fmt(c.fit.x.back()) + ": held-out " +
 fmt(c.fit.held) + ", structured " + fmt(c.fit.gap) + " (signature " + fmt(c.sig, 3) + ")");
        cands.push_back(c);
      }
      std::sort(cands.begin(), cands.end(), [](const Candidate& x, const Candidate& y) {
        return x.fit.gap != y.fit.gap ? x.fit.gap < y.fit.gap : x.sig > y.sig;
      });
      Candidate& best = cands.front();
      const double gain = 1.0 - best.fit.gap / cur.gap;
      for (Candidate& c : cands) {
        const double g = 1.0 - c.fit.gap / cur.gap;
        c.why = "held-out structured error " + fmt(cur.gap) + " -> " + fmt(c.fit.gap) + " (" + fmt(100 * g, 3) +
                " %), NRMSE " + fmt(cur.held) + " -> " + fmt(c.fit.held);
      }
      const Effect& be = catalogue()[best.effect];
      const bool null_value = best.fit.x.back() < 0.01 * (be.hi - be.lo);
      if (null_value) {
        for (Candidate& c : cands) c.why += ": rejected";
        best.why += " (fitted to its null value)";
        say("the best candidate fits to its null value: stop");
        rounds.push_back(cands);
        break;
      }
      if (gain >= kMinGain && best.fit.held < cur.held) {
        best.accepted = true;
        best.why += ": best candidate, gain >= " + fmt(100 * kMinGain) + " %: accepted";
        for (size_t i = 1; i < cands.size(); ++i) cands[i].why += ": less than the best";
        used.insert(best.effect);
        cur = best.fit;
        say("accepted " + std::string(catalogue()[best.effect].name) + " (held-out " + fmt(cur.held) +
            ", whiteness " + fmt(cur.white, 3) + ")");
        rounds.push_back(cands);
      } else {
        for (Candidate& c : cands) c.why += ": gain below " + fmt(100 * kMinGain) + " %: rejected";
        say("no candidate cuts the held-out error by " + fmt(100 * kMinGain) + " %: stop");
        rounds.push_back(cands);
        break;
      }
    }
    const bool white = cur.white <= kWhiteMax;
    const std::string verdict = white ? (cur.effects.empty() ? "no_missing_effect" : "explained") : "unexplained";

    // 3. final refit on all data, intervals
    Fit fin = fit(p, cur.effects, cur.x, 2, kMaxEvalBase);
    const auto ci = intervals(p, fin);
    const Residual r_before = residual(p, make_config(p, {}, base.x));
    const Residual r_after = residual(p, make_config(p, cur.effects, cur.x));
    // the bench's own (ODE) stand with the final model, as a check of the fast solver
    const std::vector<BenchSample> ode = simulate_bench(make_config(p, fin.effects, fin.x), p.m.t, p.m.sp);
    const Residual r_fin = residual(p, make_config(p, fin.effects, fin.x));
    double ode_diff = 0;
    for (size_t k = 0; k < n; ++k) ode_diff = std::max(ode_diff, std::fabs(ode[k].angle_deg - r_fin.sim[k].angle_deg));
    say("verdict " + verdict + "; " + std::to_string(g_evals) + " model runs");

    // 4. report.json
    nlohmann::ordered_json j;
    j["verdict"] = verdict;
    j["effects"] = nlohmann::json::array();
    for (size_t e = 0; e < fin.effects.size(); ++e) {
      const Effect& ef = catalogue()[fin.effects[e]];
      nlohmann::ordered_json je;
      je["name"] = ef.name;
      je["params"][ef.param] = fin.x[kNumBase + e];
      je["ci95"][ef.param] = {ci[kNumBase + e].first, ci[kNumBase + e].second};
      j["effects"].push_back(je);
    }
    j["gap_before"] = base.gap;
    j["gap_after"] = cur.gap;
    j["metric"] =
        "structured NRMSE on the held-out (odd) time blocks, models fitted on the even blocks: per channel "
        "(angle, and current when measured) the residual normalised by the measured channel's std, its mean "
        "square minus its white-noise part (half the mean square of first differences), floored at 0; "
        "sqrt of the mean over channels";
    j["nrmse_before"] = base.held;
    j["nrmse_after"] = cur.held;
    j["nrmse_datasheet"] = gap_datasheet;
    j["whiteness_before"] = base.white;
    j["whiteness_after"] = cur.white;
    j["whiteness_threshold"] = kWhiteMax;
    nlohmann::ordered_json jb;
    const BenchConfig fc = make_config(p, fin.effects, fin.x);
    const double bv[kNumBase] = {fc.servo.kp, fc.servo.kt, fc.servo.r, fc.load_inertia_kgm2};
    for (int i = 0; i < kNumBase; ++i) {
      jb[kBaseNames[i]]["value"] = bv[i];
      jb[kBaseNames[i]]["factor"] = fin.x[i];
      jb[kBaseNames[i]]["ci95_factor"] = {ci[i].first, ci[i].second};
    }
    j["base"] = jb;
    // regions: contiguous runs of one regime, with the base model's error there
    std::vector<std::vector<bool>> masks(kRegimes.size(), std::vector<bool>(n, false));
    for (size_t k = 0; k < n; ++k) masks[reg[k]][k] = true;
    nlohmann::ordered_json regions = nlohmann::json::array();
    for (size_t a0 = 0; a0 < n;) {
      size_t b0 = a0;
      while (b0 + 1 < n && reg[b0 + 1] == reg[a0]) ++b0;
      double e0 = 0, e1 = 0;
      for (size_t k = a0; k <= b0; ++k) e0 += sq(p, r_before, k), e1 += sq(p, r_after, k);
      const double cnt = (b0 - a0 + 1) * (p.m.has_current ? 2.0 : 1.0);
      nlohmann::ordered_json r;
      r["t0_s"] = p.m.t[a0];
      r["t1_s"] = p.m.t[b0];
      r["label"] = kRegimes[reg[a0]];
      r["error"] = std::sqrt(e0 / cnt);
      r["error_after"] = std::sqrt(e1 / cnt);
      regions.push_back(r);
      a0 = b0 + 1;
    }
    j["regions"] = regions;
    nlohmann::ordered_json jr;
    for (size_t g = 0; g < kRegimes.size(); ++g) {
      size_t c = 0;
      for (size_t k = 0; k < n; ++k) c += masks[g][k];
      if (!c) continue;
      jr[kRegimes[g]] = {{"share", double(c) / n},
                         {"error_before", metric(p, r_before, 2, &masks[g])},
                         {"error_after", metric(p, r_after, 2, &masks[g])}};
    }
    j["regimes"] = jr;
    nlohmann::ordered_json jc = nlohmann::json::array();
    for (size_t ri = 0; ri < rounds.size(); ++ri)
      for (const Candidate& c : rounds[ri])
        jc.push_back({{"round", ri + 1},
                      {"name", catalogue()[c.effect].name},
                      {"param", catalogue()[c.effect].param},
                      {"value", c.fit.x.back()},
                      {"held_out", c.fit.held},
                      {"signature", c.sig},
                      {"accepted", c.accepted},
                      {"why", c.why}});
    j["candidates"] = jc;
    j["ode_check_max_angle_diff_deg"] = ode_diff;
    j["model_runs"] = g_evals;
    write_file(a.out + "/report.json", j.dump(2) + "\n");

    // 5. plots and report.md
    std::vector<double> sb(n), sa(n), ib(n), ia(n), ra(n), rb(n);
    for (size_t k = 0; k < n; ++k) {
      sb[k] = r_before.sim[k].angle_deg, sa[k] = r_after.sim[k].angle_deg;
      ib[k] = r_before.sim[k].current_a, ia[k] = r_after.sim[k].current_a;
      rb[k] = sb[k] - p.m.angle[k], ra[k] = sa[k] - p.m.angle[k];
    }
    write_file(a.out + "/angle.svg",
               svg_chart("angle: measured vs model before / after", "deg", p.m.t,
                         {{"measured", "#000", p.m.angle}, {"set-point", "#aaa", p.m.sp},
                          {"before", "#d62728", sb}, {"after", "#1f77b4", sa}}));
    write_file(a.out + "/residual.svg",
               svg_chart("angle residual (model - measured)", "deg", p.m.t,
                         {{"before", "#d62728", rb}, {"after", "#1f77b4", ra}}));
    if (p.m.has_current)
      write_file(a.out + "/current.svg",
                 svg_chart("filtered current: measured vs model", "A", p.m.t,
                           {{"measured", "#000", p.m.current}, {"before", "#d62728", ib}, {"after", "#1f77b4", ia}}));
    std::ostringstream md;
    md << "# Servo calibration report\n\nBench file: `" << (a.bench.empty() ? "(defaults)" : a.bench)
       << "`, measurement: `" << a.measured << "` (" << n << " samples, " << fmt(span) << " s).\n\n";
    md << "**Verdict: " << verdict << "**. Gap (" << j["metric"].get<std::string>() << "): refitted base "
       << fmt(base.gap) << ", with effects " << fmt(cur.gap) << ". Plain held-out NRMSE: datasheet "
       << fmt(gap_datasheet) << ", refitted base " << fmt(base.held) << ", with effects " << fmt(cur.held)
       << ". Whiteness of the held-out residual (rms / rms of differences x sqrt 2; "
       << "noise ~1, threshold " << kWhiteMax << "): " << fmt(base.white, 3) << " -> " << fmt(cur.white, 3)
       << ".\n\n![angle](angle.svg)\n\n";
    if (p.m.has_current) md << "![current](current.svg)\n\n";
    md << "![residual](residual.svg)\n\n## Fitted parameters (all data, 95 % intervals)\n\n| parameter | value | 95 % CI |\n|---|---|---|\n";
    for (int i = 0; i < kNumBase; ++i)
      md << "| " << kBaseNames[i] << " (x datasheet) | " << fmt(fin.x[i]) << " | [" << fmt(ci[i].first) << ", "
         << fmt(ci[i].second) << "] |\n";
    for (size_t e = 0; e < fin.effects.size(); ++e)
      md << "| " << catalogue()[fin.effects[e]].name << "." << catalogue()[fin.effects[e]].param << " | "
         << fmt(fin.x[kNumBase + e]) << " | [" << fmt(ci[kNumBase + e].first) << ", "
         << fmt(ci[kNumBase + e].second) << "] |\n";
    md << "\n## Residual by regime (all data)\n\n| regime | share of time | error before | error after |\n|---|---|---|---|\n";
    for (auto it = jr.begin(); it != jr.end(); ++it)
      md << "| " << it.key() << " | " << fmt((*it)["share"].get<double>(), 3) << " | "
         << fmt((*it)["error_before"].get<double>(), 3) << " | " << fmt((*it)["error_after"].get<double>(), 3)
         << " |\n";
    md << "\n## Worst regions before\n\n| t0 (s) | t1 (s) | regime | error before | error after |\n|---|---|---|---|---|\n";
    std::vector<nlohmann::ordered_json> rs(regions.begin(), regions.end());
    std::sort(rs.begin(), rs.end(), [](const auto& x, const auto& y) { return x["error"] > y["error"]; });
    for (size_t i = 0; i < std::min<size_t>(10, rs.size()); ++i)
      md << "| " << fmt(rs[i]["t0_s"].get<double>()) << " | " << fmt(rs[i]["t1_s"].get<double>()) << " | "
         << rs[i]["label"].get<std::string>() << " | " << fmt(rs[i]["error"].get<double>(), 3) << " | "
         << fmt(rs[i]["error_after"].get<double>(), 3) << " |\n";
    md << "\n## Candidates\n\nSignature = share of the current residual in the regimes where the effect acts, "
          "over their share of time (> 1: the residual concentrates there).\n\n| round | effect | value | "
          "held-out | signature | decision |\n|---|---|---|---|---|---|\n";
    for (const auto& c : jc)
      md << "| " << c["round"].get<int>() << " | " << c["name"].get<std::string>() << " | "
         << fmt(c["value"].get<double>()) << " " << c["param"].get<std::string>() << " | "
         << fmt(c["held_out"].get<double>()) << " | " << fmt(c["signature"].get<double>(), 3) << " | "
         << c["why"].get<std::string>() << " |\n";
    if (jc.empty()) md << "| - | none tried: the refitted base already leaves a noise-like residual | | | | |\n";
    md << "\nCheck: the final model on the bench's ODE stand differs from the fast solver by at most "
       << fmt(ode_diff, 3) << " degrees.\n";
    write_file(a.out + "/report.md", md.str());
    say("wrote " + a.out + "/report.json, report.md, *.svg");
    return 0;
  } catch (const BenchError& e) {
    std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
    return 1;
  } catch (const CalError& e) {
    std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim calibrate: internal error: %s\n", e.what());
    return 3;
  }
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "fit the servo model to a bench measurement (t_s,setpoint_deg,angle_deg[,current_a]) and find which "
      "catalogue effects it is missing (docs/calibration.md)");
  sub->add_option("--bench,-b", g_args.bench, "bench file (datasheet values; docs/servo-bench.md)");
  auto* measured =
      sub->add_option("--measured,-m", g_args.measured, "measured CSV: t_s,setpoint_deg,angle_deg[,current_a]");
  sub->add_option("--out,-o", g_args.out, "output directory (report.json, report.md, SVG plots)")->required();
  sub->add_flag("--quiet,-q", g_args.quiet, "print only errors");
  // robot level: a speed table and one scene per row (robot_calibration.h)
  auto* robot = sub->add_option("--robot", g_robot.table,
                                "robot-level table: key column (e.g. slope_deg), real_speed_cm_s"
                                "[,paper_sim_speed_cm_s] (instead of --measured)");
  auto* tmpl = sub->add_option("--scene-template", g_robot.scene_template,
                               "with --robot: scene file with {slope} replaced by each row's key");
  sub->add_option("--duration", g_robot.duration_s, "with --robot: simulated seconds per run (default 6)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--window-start", g_robot.window_start_s,
                  "with --robot: the speed is measured from this time to the end (default 1 s)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--jobs,-j", g_robot.jobs, "with --robot: runs at once (default 2)")->check(CLI::Range(1, 64));
  sub->add_option("--firmware-dir", g_robot.firmware_dir, "with --robot: where the fw-* programs are");
  measured->excludes(robot);
  robot->needs(tmpl);
  tmpl->needs(robot);
  sub->callback([measured, robot] {
    if (robot->count() > 0) {
      g_robot.out = g_args.out, g_robot.quiet = g_args.quiet;
      try {
        g_exit = robotcal::run_robot(g_robot);
      } catch (const robotcal::RobotError& e) {
        std::fprintf(stderr, "chainsim calibrate: %s\n", e.what());
        g_exit = 1;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "chainsim calibrate: internal error: %s\n", e.what());
        g_exit = 3;
      }
      return;
    }
    if (measured->count() == 0) throw CLI::RequiredError("--measured or --robot");
    g_exit = run(g_args);
  });
}

int calibrate_command_exit_code() { return g_exit; }

}  // namespace chainsim
