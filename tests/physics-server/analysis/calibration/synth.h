// Synthetic servo measurements for the calibration tests and the study,
// written APART from the model code (physics-server/physics/actuators/servo_model.cpp): its own
// fine-step RK4 integration of the continuous equations with the hidden
// effect, its own backlash (a two-inertia gear with a stiff, damped contact),
// then the measurement chain: pot noise + 10-bit quantisation of the angle,
// noise + 10-bit ADC of the RC-filtered current. The true base parameters are
// a few percent off the datasheet (Table 1) written to the bench file.
//
//   ea      = duty(dz_db(theta_r - theta)) (Vs - Rs |i|),  duty = clamp(Kp e / Vs, -1, 1)
//   ea      = clamp(ea, Km wm - R Ilim, Km wm + R Ilim)       (current limit)
//   L di/dt = ea - R i - Km wm
//   rigid:    (J + Jl) dw/dt = Kt dz_th(i) - B w - Tc tanh(w/0.005) + tau_load + tau_extra(theta)
//   backlash: J dwm/dt = Kt dz_th(i) - B wm - Fc,  Jl dw/dt = Fc - Tc tanh(..) + tau_load + tau_extra
//             Fc = k (d - g/2 sign d) + c d' when |d| > g/2 (d = theta_m - theta), else 0
//   tau_f di_f/dt = |i| - i_f;  theta_r latched every frame period (pwm frames) when set
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace synth {

constexpr double kPi = 3.14159265358979323846;

struct Truth {
  // datasheet (Table 1) values written to the bench file
  double kp = 12, km = 0.14, kt = 0.14, r = 12, l = 0.0075, b = 3.5e-6, j = 7e-7, vs = 5, tau_f = 0.003;
  double jl = 3e-6, tau_load = 0.004;
  // hidden effects (0 = off)
  double i_th = 0, coulomb = 0, backlash_deg = 0, deadband_deg = 0, sag_ohm = 0, frame_s = 0, ilim = 0;
  double cogging_nm = 0;   // outside the catalogue: tau = A sin(6 theta)
  // measurement
  double angle_noise_deg = 0.2, angle_lsb_deg = 180.0 / 1023, current_noise_a = 0.002,
         current_full_a = 0.5;
  double base_spread = 0.05;  // true Kp, Km=Kt, R, Jl = datasheet x (1 +- U(spread))
};

struct Series {
  std::vector<double> t, sp, angle, current;
};

// the test set-point program, 4 s: big moves, small moves, reversals, holds
inline std::vector<std::pair<double, double>> program() {
  return {{0.0, 30},    {0.107, 120}, {0.462, 100}, {0.719, 104}, {0.955, 60},  {1.314, 63},
          {1.561, 58},  {1.806, 110}, {2.153, 90},  {2.417, 93},  {2.668, 140}, {3.002, 135},
          {3.259, 80},  {3.611, 84},  {3.866, 70}};
}

inline Series generate(const Truth& tr, unsigned seed, double duration = 4.0, double sample_s = 0.001) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-tr.base_spread, tr.base_spread);
  const double kp = tr.kp * (1 + u(rng)), kk = 1 + u(rng), r = tr.r * (1 + u(rng)), jl = tr.jl * (1 + u(rng));
  const double km = tr.km * kk, kt = tr.kt * kk;
  std::normal_distribution<double> na(0, tr.angle_noise_deg), ni(0, tr.current_noise_a);
  const auto prog = program();
  const double deg = kPi / 180;
  const double g = 0.5 * tr.backlash_deg * deg;
  const bool gear = tr.backlash_deg > 0;
  const double kc = 50.0, jred = tr.j * jl / (tr.j + jl), cc = 1.4 * std::sqrt(kc * jred);
  // state: theta, w, theta_m, wm, i, i_f (theta_m, wm used with backlash only)
  double s[6] = {prog[0].second * deg, 0, prog[0].second * deg, 0, 0, 0};
  double ref = prog[0].second * deg;
  auto dz = [](double x, double h) { return std::fabs(x) <= h ? 0.0 : x - std::copysign(h, x); };
  auto deriv = [&](const double* x, double* dx) {
    const double th = x[0], w = x[1], wm = gear ? x[3] : x[1], i = x[4];
    double e = dz(ref - th, 0.5 * tr.deadband_deg * deg);
    double ea = std::clamp(kp * e / tr.vs, -1.0, 1.0) * std::max(0.0, tr.vs - tr.sag_ohm * std::fabs(i));
    if (tr.ilim > 0) ea = std::clamp(ea, km * wm - r * tr.ilim, km * wm + r * tr.ilim);
    dx[4] = (ea - r * i - km * wm) / tr.l;
    dx[5] = (std::fabs(i) - x[5]) / tr.tau_f;
    const double tm = kt * dz(i, tr.i_th);
    const double tout = -tr.coulomb * std::tanh(w / 0.005) + tr.tau_load + tr.cogging_nm * std::sin(6 * th);
    if (!gear) {
      dx[0] = w;
      dx[1] = (tm - tr.b * w + tout) / (tr.j + jl);
      dx[2] = w;
      dx[3] = dx[1];
    } else {
      const double d = x[2] - x[0], dd = x[3] - x[1];
      double fc = 0;
      if (std::fabs(d) > g) fc = kc * (d - std::copysign(g, d)) + cc * dd;
      dx[0] = w;
      dx[1] = (fc + tout) / jl;
      dx[2] = x[3];
      dx[3] = (tm - tr.b * x[3] - fc) / tr.j;
    }
  };
  const double h = 5e-6;
  Series out;
  size_t pi = 0;
  const long long nsteps = static_cast<long long>(std::llround(duration / h));
  const long long per_sample = static_cast<long long>(std::llround(sample_s / h));
  double sp_now = prog[0].second;
  for (long long n = 0; n <= nsteps; ++n) {
    const double t = n * h;
    while (pi + 1 < prog.size() && prog[pi + 1].first <= t + 1e-12) ++pi;
    sp_now = prog[pi].second;
    if (tr.frame_s > 0) {
      // latched at the frames k * frame_s
      const double tf = std::floor(t / tr.frame_s + 1e-9) * tr.frame_s;
      size_t q = 0;
      while (q + 1 < prog.size() && prog[q + 1].first <= tf + 1e-12) ++q;
      ref = prog[q].second * deg;
    } else {
      ref = sp_now * deg;
    }
    if (n % per_sample == 0) {
      out.t.push_back(t);
      out.sp.push_back(sp_now);
      out.angle.push_back(std::round((s[0] / deg + na(rng)) / tr.angle_lsb_deg) * tr.angle_lsb_deg);
      const double c = std::clamp(std::round((s[5] + ni(rng)) / tr.current_full_a * 1023), 0.0, 1023.0);
      out.current.push_back(c * tr.current_full_a / 1023);
    }
    if (n == nsteps) break;
    double k1[6], k2[6], k3[6], k4[6], tmp[6];
    deriv(s, k1);
    for (int q = 0; q < 6; ++q) tmp[q] = s[q] + 0.5 * h * k1[q];
    deriv(tmp, k2);
    for (int q = 0; q < 6; ++q) tmp[q] = s[q] + 0.5 * h * k2[q];
    deriv(tmp, k3);
    for (int q = 0; q < 6; ++q) tmp[q] = s[q] + h * k3[q];
    deriv(tmp, k4);
    for (int q = 0; q < 6; ++q) s[q] += h / 6 * (k1[q] + 2 * k2[q] + 2 * k3[q] + k4[q]);
  }
  return out;
}

inline std::string bench_yaml(const Truth& tr) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "servo: {Kp: %g, Km: %g, Kt: %g, R: %g, L: %g, B: %g, J: %g, supply_v: %g}\n"
                "load: {inertia_kgm2: %g, torque_nm: %g}\nsensors: {current_filter_tau_s: %g}\n",
                tr.kp, tr.km, tr.kt, tr.r, tr.l, tr.b, tr.j, tr.vs, tr.jl, tr.tau_load, tr.tau_f);
  return buf;
}

inline bool write_csv(const std::string& path, const Series& s) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "t_s,setpoint_deg,angle_deg,current_a\n");
  for (size_t k = 0; k < s.t.size(); ++k)
    std::fprintf(f, "%.4f,%.3f,%.4f,%.6f\n", s.t[k], s.sp[k], s.angle[k], s.current[k]);
  return std::fclose(f) == 0;
}

// the named hidden-effect cases of the tests and the study
struct Case {
  std::string name;                  // what the calibration should report
  std::vector<std::string> expect;   // effect names (empty: no_missing_effect / unexplained)
  std::string verdict;
  Truth truth;
};

inline std::vector<Case> cases() {
  std::vector<Case> c;
  auto add = [&](const std::string& name, std::vector<std::string> ex, const std::string& v, auto set) {
    Truth t;
    set(t);
    c.push_back({name, ex, v, t});
  };
  add("null", {}, "no_missing_effect", [](Truth&) {});
  add("static_friction_threshold", {"static_friction_threshold"}, "explained", [](Truth& t) { t.i_th = 0.06; });
  add("coulomb_friction", {"coulomb_friction"}, "explained", [](Truth& t) { t.coulomb = 0.006; });
  add("backlash", {"backlash"}, "explained", [](Truth& t) { t.backlash_deg = 3; });
  add("deadband", {"deadband"}, "explained", [](Truth& t) { t.deadband_deg = 3; });
  add("supply_sag", {"supply_sag"}, "explained", [](Truth& t) { t.sag_ohm = 4; });
  add("pwm_frame_delay", {"pwm_frame_delay"}, "explained", [](Truth& t) { t.frame_s = 0.02; });
  add("current_limit", {"current_limit"}, "explained", [](Truth& t) { t.ilim = 0.22; });
  add("deadband+supply_sag", {"deadband", "supply_sag"}, "explained", [](Truth& t) {
    t.deadband_deg = 3;
    t.sag_ohm = 4;
  });
  add("cogging (outside the catalogue)", {}, "unexplained", [](Truth& t) { t.cogging_nm = 0.01; });
  return c;
}

}  // namespace synth
