// Generator B: a second, independent way of making servo records with
// backlash and supply sag, written apart from generator A (synth.h) and from
// the model (servo_model.cpp), with another integrator and other physics:
//
// * integrator: adaptive Dormand-Prince 5(4) (error per step 1e-9 relative),
//   integrated sample to sample, with the backlash's contact events located
//   by bisection of the step;
// * backlash: a rigid gear with play as a hybrid system: in the gap the rotor
//   and the output move apart; the gap closes in an impact that keeps the
//   momentum with a coefficient of restitution (the rotor bounces back,
//   closes again, ... until the rebound is below 1e-3 rad/s), then one rigid
//   body until the contact torque would pull, where it separates;
// * supply: the source Vs behind Rs feeds a rail capacitor C (470 uF) that the
//   driver draws from: C dV/dt = (Vs - V)/Rs - i_supply. A PWM bridge applies
//   duty x V and draws duty x i (braking returns current to the rail); a
//   linear driver applies clamp(Kp e, -V, V) and draws |i|.
// * deadband (deadband_deg > 0): a window comparator before the amplifier:
//   no drive while |error| < width/2, the whole error outside (analogue
//   servos); generator A's is the dead zone that subtracts the band;
// * set-point (with frames, frame_s > 0): sent as a pulse train, a pulse at
//   every frame, 1.5 ms + k (sp - 90 deg) wide for the set-point of the
//   moment it starts; the servo's decoder measures the pulse and acts on it
//   at its falling edge (as an RC servo does), so the delay of a change is
//   the time to the next frame plus that pulse's width. The integration is
//   split at each falling edge.
#pragma once

#include <array>

#include "synth_record.h"

namespace synth {
namespace b {

constexpr int kN = 7;   // theta, w, theta_m, wm, i, i_f, V
using State = std::array<double, kN>;

struct Servo {
  double kp, km, kt, r, l, b, j, jl, vs, tau_f, tau_load, g, rs, c, e;
  double db = 0;      // comparator deadband, full width, rad
  bool linear;
  bool gear;          // with play
  bool engaged = false;
  double side = 0;    // engaged: the sign of theta_m - theta
  double ref = 0;

  void deriv(const State& x, State& dx) const {
    double err = ref - x[0];
    if (std::fabs(err) < 0.5 * db) err = 0;
    const double v = rs > 0 ? x[6] : vs;
    double ea, isup;
    if (linear) {
      ea = std::clamp(kp * err, -v, v);
      isup = std::fabs(x[4]);
    } else {
      const double duty = std::clamp(kp * err / vs, -1.0, 1.0);
      ea = duty * v;
      isup = duty * x[4];
    }
    const double wm = gear ? x[3] : x[1];
    dx[4] = (ea - r * x[4] - km * wm) / l;
    dx[5] = (std::fabs(x[4]) - x[5]) / tau_f;
    dx[6] = rs > 0 ? ((vs - x[6]) / rs - isup) / c : 0.0;
    const double tm = kt * x[4];
    if (!gear || engaged) {
      const double a = (tm - b * x[1] + tau_load) / (j + jl);
      dx[0] = x[1], dx[1] = a, dx[2] = x[1], dx[3] = a;
    } else {
      dx[0] = x[1], dx[1] = tau_load / jl;
      dx[2] = x[3], dx[3] = (tm - b * x[3]) / j;
    }
  }
  // engaged: the torque the output gets from the rotor, signed by the side
  double contact(const State& x) const {
    State dx;
    deriv(x, dx);
    return side * (kt * x[4] - b * x[3] - j * dx[3]);
  }
  // > 0 while the mode holds (free: inside the play; engaged: pushing)
  double event(const State& x) const {
    if (!gear) return 1.0;
    return engaged ? contact(x) : g - std::fabs(x[2] - x[0]);
  }
};

// one Dormand-Prince step of size h: the 5th order state and the error estimate
inline void dp_step(const Servo& s, const State& x, double h, State& y, double& err) {
  static const double a21 = 1.0 / 5, a31 = 3.0 / 40, a32 = 9.0 / 40, a41 = 44.0 / 45, a42 = -56.0 / 15,
                      a43 = 32.0 / 9, a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                      a54 = -212.0 / 729, a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247,
                      a64 = 49.0 / 176, a65 = -5103.0 / 18656, b1 = 35.0 / 384, b3 = 500.0 / 1113,
                      b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84, e1 = 71.0 / 57600,
                      e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                      e7 = -1.0 / 40;
  State k1, k2, k3, k4, k5, k6, k7, t;
  s.deriv(x, k1);
  for (int q = 0; q < kN; ++q) t[q] = x[q] + h * a21 * k1[q];
  s.deriv(t, k2);
  for (int q = 0; q < kN; ++q) t[q] = x[q] + h * (a31 * k1[q] + a32 * k2[q]);
  s.deriv(t, k3);
  for (int q = 0; q < kN; ++q) t[q] = x[q] + h * (a41 * k1[q] + a42 * k2[q] + a43 * k3[q]);
  s.deriv(t, k4);
  for (int q = 0; q < kN; ++q) t[q] = x[q] + h * (a51 * k1[q] + a52 * k2[q] + a53 * k3[q] + a54 * k4[q]);
  s.deriv(t, k5);
  for (int q = 0; q < kN; ++q)
    t[q] = x[q] + h * (a61 * k1[q] + a62 * k2[q] + a63 * k3[q] + a64 * k4[q] + a65 * k5[q]);
  s.deriv(t, k6);
  for (int q = 0; q < kN; ++q) y[q] = x[q] + h * (b1 * k1[q] + b3 * k3[q] + b4 * k4[q] + b5 * k5[q] + b6 * k6[q]);
  s.deriv(y, k7);
  // error scaled per component: angles 1e-9 rad, rates 1e-6 rad/s, current 1e-9 A, rail 1e-9 V (+ relative)
  static const double scale[kN] = {1e-9, 1e-6, 1e-9, 1e-6, 1e-9, 1e-9, 1e-9};
  err = 0;
  for (int q = 0; q < kN; ++q) {
    const double eq = h * (e1 * k1[q] + e3 * k3[q] + e4 * k4[q] + e5 * k5[q] + e6 * k6[q] + e7 * k7[q]);
    err = std::max(err, std::fabs(eq) / (scale[q] + 1e-9 * std::fabs(y[q])));
  }
}

// the mode switch at an event: impact with restitution, or separation
inline void switch_mode(Servo& s, State& x) {
  if (s.engaged) {  // the contact would pull: the gap opens
    s.engaged = false;
    return;
  }
  const double d = x[2] - x[0];
  s.side = d > 0 ? 1.0 : -1.0;
  x[2] = x[0] + s.side * s.g;
  const double v = x[3] - x[1];   // closing rate (side * v > 0)
  const double p = s.j * x[3] + s.jl * x[1];
  const double w = (p + s.j * s.e * v) / (s.j + s.jl);
  if (s.e * std::fabs(v) < 1e-3) {   // the rebound is negligible: one body
    x[1] = x[3] = p / (s.j + s.jl);
    s.engaged = true;
  } else {
    x[1] = w;
    x[3] = w - s.e * v;   // bounces back into the play
    x[2] = x[0] + s.side * s.g * (1 - 1e-12);
  }
}

// integrates from t0 to t1 with the adaptive step, handling events
inline void advance(Servo& s, State& x, double t0, double t1, double& h) {
  double t = t0;
  while (t1 - t > 1e-15) {
    // a set-point change can make the contact pull at once
    if (s.gear && s.engaged && s.contact(x) <= 0) {
      s.engaged = false;
    } else if (s.gear && !s.engaged && std::fabs(x[2] - x[0]) >= s.g && (x[2] - x[0]) * (x[3] - x[1]) > 0) {
      switch_mode(s, x);   // at the edge of the play and closing: the impact now
    }
    h = std::min(h, t1 - t);
    State y;
    double err;
    dp_step(s, x, h, y, err);
    if (err > 1.0) {
      h *= std::max(0.2, 0.9 * std::pow(err, -0.2));
      continue;
    }
    if (s.event(x) > 0 && s.event(y) <= 0) {
      // locate the event: bisection on the step length
      double lo = 0, hi = h;
      State ylo = x;
      while (hi - lo > 1e-9) {
        const double mid = 0.5 * (lo + hi);
        State ym;
        double em;
        dp_step(s, x, mid, ym, em);
        if (s.event(ym) > 0) lo = mid, ylo = ym;
        else hi = mid;
      }
      dp_step(s, x, hi, y, err);
      x = y;
      t += hi;
      switch_mode(s, x);
      h = 1e-6;
      continue;
    }
    x = y;
    t += h;
    h *= std::min(5.0, 0.9 * std::pow(std::max(err, 1e-10), -0.2));
    h = std::min(h, 2e-4);
  }
}

}  // namespace b

// generator B (above): backlash, supply sag, the comparator deadband and the
// pulse train only (other effects ignored)
inline Series generate_b(const Truth& tr, unsigned seed, double duration = 4.0) {
  std::mt19937_64 rng(seed ^ 0xb0b0b0b0u);
  std::uniform_real_distribution<double> u(-tr.base_spread, tr.base_spread);
  const double deg = kPi / 180;
  b::Servo s{};
  s.kp = tr.kp * (1 + u(rng));
  const double kk = 1 + u(rng);
  s.km = tr.km * kk, s.kt = tr.kt * kk;
  s.r = tr.r * (1 + u(rng));
  s.jl = tr.jl * (1 + u(rng));
  s.l = tr.l, s.b = tr.b, s.j = tr.j, s.vs = tr.vs, s.tau_f = tr.tau_f, s.tau_load = tr.tau_load;
  s.g = 0.5 * tr.backlash_deg * deg;
  s.gear = tr.backlash_deg > 0;
  s.rs = tr.sag_ohm, s.c = tr.rail_c, s.e = tr.restitution, s.linear = tr.linear_driver;
  s.db = tr.deadband_deg * deg;
  Series out;
  out.has_current = tr.current_column;
  out.t = sample_times(tr, duration, 1e-6, rng);
  out.sp = sampled_program(out.t);
  Meter meter(tr);
  b::State x = {out.sp[0] * deg, 0, out.sp[0] * deg, 0, 0, 0, tr.vs};
  double h = 1e-6;
  // the pulses' falling edges and the set-points they carry (the set-point
  // of the sample interval their frame falls in)
  std::vector<std::pair<double, double>> latch;
  if (tr.frame_s > 0) {
    size_t j = 0;
    for (double e = tr.frame_phase_s; e < out.t.back(); e += tr.frame_s) {
      while (j + 1 < out.t.size() && out.t[j + 1] <= e) ++j;
      const double w = 1.5e-3 + tr.pulse_s_per_deg * (out.sp[j] - 90);
      latch.push_back({e + w, out.sp[j]});
    }
  }
  size_t next = 0;
  double held = out.sp[0];   // before the first pulse ends: the set-point it had
  for (size_t k = 0; k < out.t.size(); ++k) {
    if (k > 0 && tr.frame_s > 0) {
      double t = out.t[k - 1];
      for (; next < latch.size() && latch[next].first < out.t[k]; ++next) {
        s.ref = held * deg;
        if (latch[next].first > t) b::advance(s, x, t, latch[next].first, h), t = latch[next].first;
        held = latch[next].second;
      }
      s.ref = held * deg;
      b::advance(s, x, t, out.t[k], h);
    } else if (k > 0) {
      s.ref = out.sp[k - 1] * deg;
      b::advance(s, x, out.t[k - 1], out.t[k], h);
    }
    out.angle.push_back(meter.angle(x[0] / deg, rng));
    out.current.push_back(meter.current(x[5], rng));
  }
  return out;
}

}  // namespace synth
