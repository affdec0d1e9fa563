// Generator C: the held-out generator of servo-bench records (issue 40).
// It shares no code with the model (servo_model.cpp), generator A (synth.h),
// generator B (synth_b.h) or their record helpers (synth_record.h): its
// servo, its set-point profiles, its recording conditions, its meter and its
// files are its own, written from the physics. The calibration is never
// tuned on it (docs/calibration.md, "Held-out judgement").
//
// Everything is referred to the output shaft (the datasheet's J, Km and Kt
// are, scenes/bench/servo-default.yaml).
//
// * motor:   L di/dt = v - R i - Ke wm,  J dwm/dt = Kt i - B wm - Ff_m(wm, zm) - Tg
//   output:  Jl dw/dt = Tg - Ff_o(w, zo) + tau_load + tau_spring(theta)
//   integrated by Boost.Odeint's Cash-Karp 5(4) with step-size control
//   (abs 1e-10, rel 1e-8, step <= 50 us), between events (samples, the
//   servo's pulse decoding, the ADC's holds), after 0.5 s of holding the
//   first set-point;
// * gear: two inertias (rotor side J, output side Jl) coupled by a stiff,
//   damped mesh Tg = k (d - g sign d) + c d' only while the play is closed,
//   |d| > g (d = theta_m - theta, g half the play); the contact pushes,
//   never pulls. Without backlash the mesh is the same spring without play;
// * friction: LuGre (bristle state z per side): dz/dt = v - s0 |v| z / S(v),
//   S(v) = Fc + (Fs - Fc) exp(-(v/vs)^2) (the Stribeck curve, N m),
//   F = s0 z + s1 exp(-(v/vd)^2) dz/dt. At the rotor (a static friction that
//   the current must overcome: labelled the catalogue's
//   static_friction_threshold) or at the output (Coulomb friction);
// * servo electronics: the bench sends the set-point as a pulse train (period
//   T, a random phase against the set-point changes, width 1.5 ms + (sp - 90
//   deg) / 90 deg x 1 ms, the command in force at the rising edge); the servo
//   decodes a pulse at its falling edge. Error through a deadband (inside: no
//   drive; outside: the whole error, as an analogue servo's comparator does),
//   duty = clamp(Kp e / Vs, -1, 1) of an H-bridge on the rail V; the rail is
//   a capacitor C charged from the supply Vs through its source resistance
//   Rs and drawn by the bridge (duty x i); a current limit by a sense
//   amplifier that takes Ki (|i| - Ilim) volts off the drive above the limit;
// * bench sensors: the output angle on a 10-bit ADC (200 deg span), the
//   motor current |i| through the bench's RC filter on a 10-bit ADC (0.6 A
//   span), one multiplexed ADC: angle held at the sample time, current 25 us
//   later; white noise plus first-order filtered (coloured) noise per
//   channel; a sample clock with a crystal error and jitter.
// * outside the catalogue: a return spring on the output (torque
//   -ks (theta - rest)), and a bowed feedback potentiometer in the servo (it
//   reads theta + a sin(2 pi theta / P + phi), so it holds the output off the
//   set-point by a position-dependent amount).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/numeric/odeint.hpp>

namespace synth_c {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

// ---------------------------------------------------------------- friction

// LuGre friction on one side of the gear (fs = 0: none)
struct Lugre {
  double fc = 0, fs = 0;   // Coulomb and static levels, N m
  double vs = 0.02;        // Stribeck velocity, rad/s
  double s0 = 0, s1 = 0;   // bristle stiffness N m/rad, damping N m s/rad
  double vd = 0.05;        // the bristle damping fades above this speed, rad/s

  bool on() const { return fs > 0; }
  // the Stribeck curve: the steady friction level at speed v
  double level(double v) const { return fc + (fs - fc) * std::exp(-(v / vs) * (v / vs)); }
  double dz(double v, double z) const { return on() ? v - s0 * std::fabs(v) * z / level(v) : 0.0; }
  double torque(double v, double z) const {
    return on() ? s0 * z + s1 * std::exp(-(v / vd) * (v / vd)) * dz(v, z) : 0.0;
  }
  // the steady-state friction at a constant speed v (dz = 0): sign(v) level(v)
  double steady(double v) const { return v == 0 ? 0.0 : std::copysign(level(v), v); }
};

// a LuGre side whose bristles deflect 0.01 deg at the static level (below
// the angle's resolution), damped near critically on inertia j
inline Lugre lugre(double fc, double fs, double vs, double j) {
  Lugre f;
  f.fc = fc, f.fs = fs, f.vs = vs;
  f.s0 = fs / (0.01 * kDeg);
  f.s1 = 1.4 * std::sqrt(f.s0 * j);
  return f;
}

// ---------------------------------------------------------------- the servo

struct Servo {
  // base, true values (datasheet x a few %)
  double kp = 12, ke = 0.14, kt = 0.14, r = 12, l = 0.0075, b = 3.5e-6, j = 7e-7;
  double jl = 3e-6, tau_load = 0;
  // supply: Vs behind Rs into a rail capacitor (rs = 0: a stiff supply)
  double vs = 5, rs = 0, rail_c = 220e-6;
  // gear mesh: half play g (rad), stiffness k, damping c
  double g = 0, k_mesh = 50, c_mesh = 0;
  Lugre motor, output;
  double deadband = 0;          // full width, rad
  double ilim = 0, k_ilim = 150;   // current limit A (0: none), sense gain V/A
  double frame_s = 0, frame_phase_s = 0;   // pulse train (0: the set-point reaches the servo directly)
  double spring_k = 0, spring_rest = 0;    // outside: return spring, N m/rad, rad
  double bow = 0, bow_period = 1, bow_phase = 0;   // outside: feedback pot bow, rad, rad, rad
  double tau_f = 0.003;         // the bench's RC filter on |i|
};

// the pulse width that carries a set-point (deg): 1.5 ms at 90 deg, +-1 ms per 90 deg
inline double pulse_width_s(double sp_deg) { return 1.5e-3 + (sp_deg - 90) / 90 * 1e-3; }

// the gear mesh torque from the rotor to the output: only with the play closed, pushing
inline double mesh_torque(const Servo& s, double d, double dd) {
  if (std::fabs(d) <= s.g) return 0.0;
  const double t = s.k_mesh * (d - std::copysign(s.g, d)) + s.c_mesh * dd;
  if (s.g > 0 && t * d < 0) return 0.0;   // teeth in contact push, they do not pull
  return t;
}

// the drive voltage the bridge applies for the reference ref (rad) at state
// (theta, i, rail v): deadband, duty, current limit
inline double drive_voltage(const Servo& s, double ref, double theta, double i, double v) {
  const double pot = theta + s.bow * std::sin(2 * kPi * theta / s.bow_period + s.bow_phase);
  const double e = ref - pot;
  if (std::fabs(e) < 0.5 * s.deadband) return 0.0;
  double u = std::clamp(s.kp * e / s.vs, -1.0, 1.0) * v;
  if (s.ilim > 0 && std::fabs(i) > s.ilim && u * i > 0) {
    const double cut = s.k_ilim * (std::fabs(i) - s.ilim);
    u = std::fabs(u) > cut ? u - std::copysign(cut, u) : 0.0;
  }
  return u;
}

constexpr int kN = 9;   // i, theta_m, wm, theta, w, z_m, z_o, i_f, v_rail
using State = std::array<double, kN>;

struct System {
  const Servo& s;
  double ref = 0;   // the reference the servo's electronics hold (rad)

  void operator()(const State& x, State& dx, double /*t*/) const {
    const double i = x[0], thm = x[1], wm = x[2], th = x[3], w = x[4], v = x[8];
    const double u = drive_voltage(s, ref, th, i, v);
    const double tg = mesh_torque(s, thm - th, wm - w);
    dx[0] = (u - s.r * i - s.ke * wm) / s.l;
    dx[1] = wm;
    dx[2] = (s.kt * i - s.b * wm - s.motor.torque(wm, x[5]) - tg) / s.j;
    dx[3] = w;
    dx[4] = (tg - s.output.torque(w, x[6]) + s.tau_load - s.spring_k * (th - s.spring_rest)) / s.jl;
    dx[5] = s.motor.dz(wm, x[5]);
    dx[6] = s.output.dz(w, x[6]);
    dx[7] = (std::fabs(i) - x[7]) / s.tau_f;
    // the bridge draws duty x i from the rail (u / v is the duty)
    dx[8] = s.rs > 0 ? ((s.vs - v) / s.rs - (v > 1e-9 ? u / v * i : 0.0)) / s.rail_c : 0.0;
  }
};

// integrates the servo from t0 to t1 with the reference held
inline void advance(const Servo& s, double ref, State& x, double t0, double t1) {
  namespace odeint = boost::numeric::odeint;
  if (t1 <= t0) return;
  System sys{s, ref};
  auto stepper = odeint::make_controlled(1e-10, 1e-8, 50e-6, odeint::runge_kutta_cash_karp54<State>());
  odeint::integrate_adaptive(stepper, sys, x, t0, t1, std::min(1e-6, t1 - t0));
}

// ---------------------------------------------------------------- conditions

// a seed's recording conditions: noise level, rate, load, profile, channels
struct Conditions {
  int noise = 1;            // 0, 1, 2 (sd in Meter)
  double sample_hz = 500;   // the bench's nominal rate
  double clock_ppm = 0;     // its crystal's error
  double jitter = 0;        // timestamps jitter by +-this fraction of the interval
  bool current = true;      // the record has current_a
  double jl = 3e-6, tau_load = 0;   // the load as the bench file gives it
  int profile = 0;          // 0 steps, 1 staircase, 2 sine then steps
  double duration = 5;      // s
  unsigned profile_seed = 0;
};

inline Conditions conditions(unsigned seed) {
  std::mt19937_64 rng(0xc0d1c000u + seed);
  std::uniform_real_distribution<double> u(0, 1);
  Conditions c;
  c.noise = static_cast<int>(seed % 3);
  c.profile = static_cast<int>((seed / 3) % 3);
  c.current = seed % 5 != 2;
  c.sample_hz = 100.0 * std::pow(20.0, u(rng));   // log-uniform 100 Hz - 2 kHz
  c.clock_ppm = 200 * (2 * u(rng) - 1);
  c.jitter = 0.1 * u(rng);
  const double loads[3] = {3e-6, 1e-5, 2.5e-5};
  c.jl = loads[static_cast<int>(u(rng) * 3) % 3];
  const double torques[3] = {0.0, 0.004, -0.006};
  c.tau_load = torques[static_cast<int>(u(rng) * 3) % 3];
  c.duration = 4 + 2 * u(rng);
  c.profile_seed = static_cast<unsigned>(rng());
  return c;
}

// ---------------------------------------------------------------- the meter

struct Meter {
  double angle_white = 0.1, angle_col = 0.1, current_white = 0.0015, current_col = 0.001;   // sd: deg, A
  double col_tau = 0.01;             // the coloured noise's correlation time, s
  double angle_lsb = 200.0 / 1024;   // 10 bits over 200 deg
  double current_lsb = 0.6 / 1024;   // 10 bits over 0.6 A
  double mux_s = 25e-6;              // the current is held this long after the angle
  bool exact = false;                // no noise, no quantisation (the effect size)

  double angle_sd() const {
    return std::sqrt(angle_white * angle_white + angle_col * angle_col + angle_lsb * angle_lsb / 12);
  }
  double current_sd() const {
    return std::sqrt(current_white * current_white + current_col * current_col + current_lsb * current_lsb / 12);
  }
};

inline Meter meter_for(const Conditions& c, std::mt19937_64& rng) {
  const double f[3] = {0.4, 1.0, 2.5};
  Meter m;
  m.angle_white = 0.08 * f[c.noise], m.angle_col = 0.06 * f[c.noise];
  m.current_white = 0.0012 * f[c.noise], m.current_col = 0.0008 * f[c.noise];
  m.col_tau = 0.005 * std::pow(6.0, std::uniform_real_distribution<double>(0, 1)(rng));   // 5-30 ms
  return m;
}

// a 10-bit ADC: the held value rounded to its code, clamped to the span
inline double adc(double v, double lsb, double lo) {
  const double code = std::clamp(std::round((v - lo) / lsb), 0.0, 1023.0);
  return lo + code * lsb;
}

// first-order filtered white noise of sd `sd` sampled at increasing times
inline std::vector<double> coloured_noise(const std::vector<double>& t, double sd, double tau, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  std::vector<double> x(t.size());
  double s = sd * n(rng);   // stationary from the start
  for (size_t k = 0; k < t.size(); ++k) {
    if (k > 0) {
      const double a = std::exp(-(t[k] - t[k - 1]) / tau);
      s = a * s + sd * std::sqrt(1 - a * a) * n(rng);
    }
    x[k] = s;
  }
  return x;
}

// ---------------------------------------------------------------- profiles

// the bench's sample times: nominal rate with the crystal's error, jittered
inline std::vector<double> sample_times(const Conditions& c, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-c.jitter, c.jitter);
  const double dt = 1.0 / (c.sample_hz * (1 + 1e-6 * c.clock_ppm));
  std::vector<double> t;
  for (long k = 0;; ++k) {
    double tk = std::round(((k + (k ? u(rng) : 0.0)) * dt) * 1e6) * 1e-6;   // timestamps in us
    if (tk > c.duration) break;
    if (!t.empty() && tk <= t.back()) tk = t.back() + 1e-6;
    t.push_back(tk);
  }
  return t;
}

// the set-point program as (time, deg) changes, per profile
inline std::vector<std::pair<double, double>> program(const Conditions& c) {
  std::mt19937_64 rng(c.profile_seed);
  std::uniform_real_distribution<double> u(0, 1);
  auto U = [&](double a, double b) { return a + (b - a) * u(rng); };
  std::vector<std::pair<double, double>> p;
  double t = 0, sp = U(50, 130);
  auto steps = [&](double until) {
    while (t < until) {
      p.push_back({t, std::round(sp * 100) / 100});
      t += U(0.15, 0.45);
      const double move = u(rng) < 0.5 ? U(25, 80) : U(1.5, 6);
      sp += u(rng) < 0.5 ? move : -move;
      if (sp < 20 || sp > 160) sp -= 2 * (sp < 20 ? sp - 20 : sp - 160);   // reflect into the range
      sp = std::clamp(sp, 20.0, 160.0);
    }
  };
  if (c.profile == 0) {
    steps(c.duration);
  } else if (c.profile == 1) {
    // a staircase up and down in small steps, then a big return and steps
    sp = U(40, 60);
    const double up = U(3, 8);
    while (t < 0.6 * c.duration && sp < 140) p.push_back({t, sp}), t += U(0.12, 0.3), sp += up;
    while (t < 0.8 * c.duration && sp > 40) p.push_back({t, sp}), t += U(0.12, 0.3), sp -= up;
    steps(c.duration);
  } else {
    // a sine the servo follows (the set-point changes every 5 ms), then steps
    const double a = U(20, 50), f = U(0.5, 1.5), mid = U(70, 110);
    for (; t < 0.4 * c.duration; t += 0.005) p.push_back({t, std::round((mid + a * std::sin(2 * kPi * f * t)) * 100) / 100});
    sp = mid;
    steps(c.duration);
  }
  return p;
}

// ---------------------------------------------------------------- the record

struct Record {
  std::vector<double> t, sp, angle, current;
  bool has_current = true;
};

// what a record is made from: the servo, the conditions and the meter
struct Truth {
  Servo servo;
  Conditions cond;
  Meter meter;
};

// the set-point (deg) in force at time tau: the last sample at or before it
inline double command_at(const Record& r, double tau) {
  const size_t k = std::upper_bound(r.t.begin(), r.t.end(), tau + 1e-12) - r.t.begin();
  return r.sp[k == 0 ? 0 : k - 1];
}

// the record of `tr`; the seed draws the sample times and the noise (the
// same seed gives the same times whatever the servo)
inline Record generate(const Truth& tr, unsigned seed) {
  std::mt19937_64 clock_rng(0xc1c1c100u + seed), noise_rng(0xc2c2c200u + seed);
  const Servo& s = tr.servo;
  const Meter& m = tr.meter;
  Record out;
  out.has_current = tr.cond.current;
  out.t = sample_times(tr.cond, clock_rng);
  const auto prog = program(tr.cond);
  size_t p = 0;
  for (double tk : out.t) {   // the bench commands on its sample clock
    while (p + 1 < prog.size() && prog[p + 1].first <= tk + 1e-12) ++p;
    out.sp.push_back(prog[p].second);
  }
  // events: 0 angle hold (and, without frames, the new command), 1 current
  // hold, 2 a pulse decoded (its set-point)
  struct Event {
    double t;
    int kind;
    double value;
  };
  std::vector<Event> ev;
  for (size_t k = 0; k < out.t.size(); ++k) {
    ev.push_back({out.t[k], 0, out.sp[k]});
    ev.push_back({out.t[k] + m.mux_s, 1, 0});
  }
  if (s.frame_s > 0)
    for (double tn = s.frame_phase_s; tn < out.t.back() + m.mux_s; tn += s.frame_s) {
      const double sp = command_at(out, tn);
      ev.push_back({tn + pulse_width_s(sp), 2, sp});
    }
  std::stable_sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) { return a.t < b.t; });
  // holding the first set-point for 0.5 s before the record starts
  double ref = out.sp[0] * kDeg;
  State x = {0, ref, 0, ref, 0, 0, 0, 0, s.vs};
  advance(s, ref, x, -0.5, 0.0);
  std::vector<double> angle, current;
  double t = 0;
  for (const Event& e : ev) {
    advance(s, ref, x, t, e.t);
    t = std::max(t, e.t);
    if (e.kind == 0) {
      angle.push_back(x[3] / kDeg);
      if (s.frame_s <= 0) ref = e.value * kDeg;
    } else if (e.kind == 1) {
      current.push_back(x[7]);
    } else {
      ref = e.value * kDeg;
    }
  }
  const std::vector<double> na = coloured_noise(out.t, m.angle_col, m.col_tau, noise_rng);
  const std::vector<double> ni = coloured_noise(out.t, m.current_col, m.col_tau, noise_rng);
  std::normal_distribution<double> wa(0, m.angle_white), wi(0, m.current_white);
  for (size_t k = 0; k < out.t.size(); ++k) {
    const double a = angle[k] + na[k] + wa(noise_rng), i = current[k] + ni[k] + wi(noise_rng);
    out.angle.push_back(m.exact ? angle[k] : adc(a, m.angle_lsb, -10.0));
    out.current.push_back(m.exact ? current[k] : adc(i, m.current_lsb, 0.0));
  }
  return out;
}

// ---------------------------------------------------------------- files

// the bench file: the datasheet (scenes/bench/servo-default.yaml) and the load the bench knows
inline std::string bench_yaml(const Conditions& c) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "servo: {Kp: 12, Km: 0.14, Kt: 0.14, R: 12, L: 0.0075, B: 3.5e-6, J: 7e-7, supply_v: 5}\n"
                "load: {inertia_kgm2: %g, torque_nm: %g}\nsensors: {current_filter_tau_s: 0.003}\n",
                c.jl, c.tau_load);
  return buf;
}

inline bool write_csv(const std::string& path, const Record& r) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fputs(r.has_current ? "t_s,setpoint_deg,angle_deg,current_a\n" : "t_s,setpoint_deg,angle_deg\n", f);
  for (size_t k = 0; k < r.t.size(); ++k) {
    std::fprintf(f, "%.6f,%.2f,%.4f", r.t[k], r.sp[k], r.angle[k]);
    if (r.has_current) std::fprintf(f, ",%.6f", r.current[k]);
    std::fputc('\n', f);
  }
  return std::fclose(f) == 0;
}

// ---------------------------------------------------------------- cases

// draws log-uniform in [a, b]
inline double log_uniform(std::mt19937_64& rng, double a, double b) {
  return a * std::pow(b / a, std::uniform_real_distribution<double>(0, 1)(rng));
}

// every effect generator C can hide: the catalogue's, then two outside it
const std::string kEffects[] = {"static_friction_threshold", "coulomb_friction", "backlash", "deadband", "supply_sag",
                                "pwm_frame_delay", "current_limit", "return_spring", "pot_bow"};

// sets one effect on the servo, its size drawn over the plausible range down
// to about the smallest a 10-bit bench should show
inline void set_effect(const std::string& name, Servo& s, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  if (name == "static_friction_threshold") {
    // rotor-side friction, breakaway 0.02-0.1 A worth of torque
    const double fs = s.kt * log_uniform(rng, 0.02, 0.10);
    s.motor = lugre(fs * (0.6 + 0.3 * u(rng)), fs, log_uniform(rng, 0.01, 0.05), s.j);
  } else if (name == "coulomb_friction") {
    const double fc = log_uniform(rng, 0.002, 0.010);
    s.output = lugre(fc, fc * (1 + 0.3 * u(rng)), log_uniform(rng, 0.01, 0.05), s.jl);
  } else if (name == "backlash") {
    s.g = 0.5 * log_uniform(rng, 0.8, 5.0) * kDeg;
  } else if (name == "deadband") {
    s.deadband = log_uniform(rng, 0.8, 5.0) * kDeg;
  } else if (name == "supply_sag") {
    s.rs = log_uniform(rng, 1.5, 6.0);
  } else if (name == "pwm_frame_delay") {
    s.frame_s = 0.010 + 0.015 * u(rng);
    s.frame_phase_s = s.frame_s * u(rng);
  } else if (name == "current_limit") {
    s.ilim = log_uniform(rng, 0.10, 0.25);
    s.k_ilim = log_uniform(rng, 80, 300);
  } else if (name == "return_spring") {
    s.spring_k = log_uniform(rng, 0.004, 0.012);   // N m at a radian off its rest
    s.spring_rest = (40 + 100 * u(rng)) * kDeg;
  } else if (name == "pot_bow") {
    s.bow = log_uniform(rng, 0.8, 2.5) * kDeg;
    s.bow_period = (150 + 100 * u(rng)) * kDeg;
    s.bow_phase = 2 * kPi * u(rng);
  } else {
    throw std::invalid_argument("synth_c: no effect named " + name);
  }
}

struct Case {
  std::string name;
  std::vector<std::string> hidden;   // what the servo has (catalogue names, or outside ones)
  std::vector<std::string> expect;   // what a perfect method names
  std::string verdict;               // and its verdict
};

inline bool outside_catalogue(const std::string& e) { return e == "return_spring" || e == "pot_bow"; }

// the true servo and meter of a case at a seed: the base a few % off the
// datasheet (Kp, Km = Kt, R, Jl), the gear mesh and rail capacitor drawn,
// then the case's effects
inline Truth truth(const Case& c, unsigned seed) {
  Truth tr;
  tr.cond = conditions(seed);
  std::mt19937_64 rng(0xc3c3c300u + seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05), v(0, 1);
  Servo& s = tr.servo;
  s.kp *= 1 + u(rng);
  const double kk = 1 + u(rng);
  s.ke *= kk, s.kt *= kk;
  s.r *= 1 + u(rng);
  s.jl = tr.cond.jl * (1 + u(rng));
  s.tau_load = tr.cond.tau_load;
  s.k_mesh = log_uniform(rng, 20, 100);
  s.c_mesh = 2 * (0.2 + 0.4 * v(rng)) * std::sqrt(s.k_mesh * s.j * s.jl / (s.j + s.jl));
  s.rail_c = log_uniform(rng, 47e-6, 470e-6);
  tr.meter = meter_for(tr.cond, rng);
  // each effect from its own stream (by its place in kEffects), so that a
  // pair draws what its singles draw
  for (const std::string& e : c.hidden) {
    const size_t n = std::find(std::begin(kEffects), std::end(kEffects), e) - std::begin(kEffects);
    std::mt19937_64 er(0xc4c4c400u + seed * 16 + n);
    set_effect(e, s, er);
  }
  return tr;
}

// the cases of the held-out study
inline std::vector<Case> cases() {
  const std::vector<std::string> catalogue = {"static_friction_threshold", "coulomb_friction", "backlash", "deadband",
                                              "supply_sag", "pwm_frame_delay", "current_limit"};
  std::vector<Case> c;
  c.push_back({"C: null", {}, {}, "no_missing_effect"});
  for (const std::string& e : catalogue) c.push_back({"C: " + e, {e}, {e}, "explained"});
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"pwm_frame_delay", "backlash"},       {"backlash", "supply_sag"},
      {"current_limit", "supply_sag"},       {"coulomb_friction", "backlash"},
      {"static_friction_threshold", "current_limit"}, {"deadband", "pwm_frame_delay"}};
  for (const auto& [a, b] : pairs) c.push_back({"C: " + a + "+" + b, {a, b}, {a, b}, "explained"});
  c.push_back({"C: return spring (outside the catalogue)", {"return_spring"}, {}, "unexplained"});
  c.push_back({"C: bowed feedback pot (outside the catalogue)", {"pot_bow"}, {}, "unexplained"});
  return c;
}

inline Case case_named(const std::string& name) {
  for (const Case& c : cases())
    if (c.name == name) return c;
  return {};
}

// an effect's size in the record: the noiseless records with and without
// it apart, summed over the samples as (difference / the meter's sd)^2 per
// recorded channel (as synth::effect_size does for A and B)
inline double effect_size(const Case& c, unsigned seed, const std::string& name) {
  Case without = c;
  without.hidden.erase(std::remove(without.hidden.begin(), without.hidden.end(), name), without.hidden.end());
  Truth a = truth(c, seed), b = truth(without, seed);
  a.meter.exact = b.meter.exact = true;
  const Record ra = generate(a, seed), rb = generate(b, seed);
  double s = 0;
  for (size_t k = 0; k < ra.t.size(); ++k) {
    const double da = (ra.angle[k] - rb.angle[k]) / a.meter.angle_sd();
    const double di = a.cond.current ? (ra.current[k] - rb.current[k]) / a.meter.current_sd() : 0.0;
    s += da * da + di * di;
  }
  return s;
}

// An effect whose size in the record is below this is not in the record: a
// perfect method does not name it (fixed before the study was run; the
// study's table of A and B gives "below 10" as the bin nothing can name)
constexpr double kShown = 25;

// what a perfect method answers on a case's record at a seed: the catalogue
// effects the record shows; unexplained when it shows one outside the
// catalogue; and the size of the weakest hidden effect (-1: none hidden)
struct Answer {
  std::vector<std::string> expect;
  std::string verdict;
  double weakest = -1;
};

inline Answer perfect_answer(const Case& c, unsigned seed) {
  Answer a;
  bool outside = false;
  for (const std::string& e : c.hidden) {
    const double s = effect_size(c, seed, e);
    a.weakest = a.weakest < 0 ? s : std::min(a.weakest, s);
    if (s < kShown) continue;
    if (outside_catalogue(e)) outside = true;
    else a.expect.push_back(e);
  }
  a.verdict = outside ? "unexplained" : a.expect.empty() ? "no_missing_effect" : "explained";
  if (outside) a.expect.clear();
  return a;
}

// the truth file: what a perfect method answers, and the hidden servo
inline std::string truth_json(const Case& c, const Answer& a, const Truth& tr) {
  std::string expect;
  for (const std::string& e : a.expect) expect += (expect.empty() ? "\"" : ", \"") + e + "\"";
  const Servo& s = tr.servo;
  char buf[2048];
  std::snprintf(buf, sizeof buf,
                "{\"case\": \"%s\", \"verdict\": \"%s\", \"effects\": [%s], \"weakest_size\": %.6g,\n"
                " \"servo\": {\"kp\": %.6g, \"km\": %.6g, \"r\": %.6g, \"jl\": %.6g, \"tau_load\": %.6g,"
                " \"backlash_deg\": %.6g, \"mesh_k\": %.6g, \"motor_fs_nm\": %.6g, \"motor_fc_nm\": %.6g,"
                " \"output_fs_nm\": %.6g, \"output_fc_nm\": %.6g, \"deadband_deg\": %.6g, \"rs_ohm\": %.6g,"
                " \"rail_uf\": %.6g, \"frame_ms\": %.6g, \"phase_ms\": %.6g, \"ilim_a\": %.6g,"
                " \"spring_nm_rad\": %.6g, \"pot_bow_deg\": %.6g},\n"
                " \"record\": {\"sample_hz\": %.6g, \"noise\": %d, \"profile\": %d, \"current\": %s, \"duration_s\": %.6g}}\n",
                c.name.c_str(), a.verdict.c_str(), expect.c_str(), a.weakest, s.kp, s.ke, s.r, s.jl, s.tau_load,
                2 * s.g / kDeg, s.k_mesh, s.motor.fs, s.motor.fc, s.output.fs, s.output.fc, s.deadband / kDeg, s.rs,
                s.rail_c * 1e6, s.frame_s * 1e3, s.frame_phase_s * 1e3, s.ilim, s.spring_k, s.bow / kDeg,
                tr.cond.sample_hz, tr.cond.noise, tr.cond.profile, tr.cond.current ? "true" : "false",
                tr.cond.duration);
  return buf;
}

// writes bench.yaml, m.csv and truth.json of a case at a seed into dir; the
// perfect answer
inline Answer write_case(const Case& c, unsigned seed, const std::string& dir) {
  const Truth tr = truth(c, seed);
  const Answer a = perfect_answer(c, seed);
  std::FILE* f = std::fopen((dir + "/bench.yaml").c_str(), "w");
  if (f) std::fputs(bench_yaml(tr.cond).c_str(), f), std::fclose(f);
  write_csv(dir + "/m.csv", generate(tr, seed));
  f = std::fopen((dir + "/truth.json").c_str(), "w");
  if (f) std::fputs(truth_json(c, a, tr).c_str(), f), std::fclose(f);
  return a;
}

}  // namespace synth_c
