// Generator A of synthetic servo measurements for the calibration tests and
// the study, written APART from the model code
// (physics-server/physics/actuators/servo_model.cpp): its own fine-step RK4
// integration (5 us) of the continuous equations with the hidden effects,
// its own backlash (a two-inertia gear with a stiff, damped contact), then the
// measurement chain of synth_record.h. The true base parameters are a few
// percent off the datasheet (Table 1) written to the bench file.
//
//   ea      = duty(dz_db(theta_r - theta)) (Vs - Rs |i|),  duty = clamp(Kp e / Vs, -1, 1)
//   ea      = clamp(ea, Km wm - R Ilim, Km wm + R Ilim)       (current limit)
//   L di/dt = ea - R i - Km wm
//   rigid:    (J + Jl) dw/dt = Kt dz_th(i) - B w - Tc tanh(w/0.005) + tau_load + tau_extra(theta)
//   backlash: J dwm/dt = Kt dz_th(i) - B wm - Fc,  Jl dw/dt = Fc - Tc tanh(..) + tau_load + tau_extra
//             Fc = k (d - g/2 sign d) + c d' when |d| > g/2 (d = theta_m - theta), else 0
//   tau_f di_f/dt = |i| - i_f;  theta_r = the set-point at the last pwm frame (phase + n period) when set
#pragma once

#include "synth_record.h"

namespace synth {

inline Series generate(const Truth& tr, unsigned seed, double duration = 4.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-tr.base_spread, tr.base_spread);
  const double kp = tr.kp * (1 + u(rng)), kk = 1 + u(rng), r = tr.r * (1 + u(rng)), jl = tr.jl * (1 + u(rng));
  const double km = tr.km * kk, kt = tr.kt * kk;
  const double h = 5e-6;
  Series out;
  out.has_current = tr.current_column;
  out.t = sample_times(tr, duration, h, rng);
  out.sp = sampled_program(out.t);
  Meter meter(tr);
  const double deg = kPi / 180;
  const double g = 0.5 * tr.backlash_deg * deg;
  const bool gear = tr.backlash_deg > 0;
  const double kc = tr.backlash_k, jred = tr.j * jl / (tr.j + jl), cc = 1.4 * std::sqrt(kc * jred);
  // the set-point in force at time tau (changes act from their sample)
  auto setpoint_at = [&](double tau) {
    const size_t k = std::upper_bound(out.t.begin(), out.t.end(), tau + 1e-12) - out.t.begin();
    return out.sp[k == 0 ? 0 : k - 1];
  };
  // state: theta, w, theta_m, wm, i, i_f (theta_m, wm used with backlash only)
  double s[6] = {out.sp[0] * deg, 0, out.sp[0] * deg, 0, 0, 0};
  double ref = out.sp[0] * deg;
  auto dz = [](double x, double hw) { return std::fabs(x) <= hw ? 0.0 : x - std::copysign(hw, x); };
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
  long long n = 0;
  for (size_t k = 0; k < out.t.size(); ++k) {
    const long long n_end = std::llround(out.t[k] / h);
    for (; n < n_end; ++n) {
      const double t = n * h;
      if (tr.frame_s > 0) {
        // latched at the frames phase + m period, the first at the phase
        const double m = std::floor((t - tr.frame_phase_s) / tr.frame_s + 1e-9);
        ref = (m < 0 ? out.sp[0] : setpoint_at(tr.frame_phase_s + m * tr.frame_s)) * deg;
      } else {
        ref = setpoint_at(t) * deg;
      }
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
    out.angle.push_back(meter.angle(s[0] / deg, rng));
    out.current.push_back(meter.current(s[5], rng));
  }
  return out;
}

}  // namespace synth
