// What the synthetic generators (synth.h, synth_b.h) share: the true servo
// they are given, the recording conditions (rate, timestamp jitter, noise,
// load, whether the current is recorded), the set-point program, the record
// and its files. The physics is each generator's own.
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
  double frame_phase_s = 0;   // first frame after the record starts
  double backlash_k = 50;     // generator A: gear contact stiffness, N m/rad
  double cogging_nm = 0;      // outside the catalogue: tau = A sin(6 theta)
  // generator B's forms (synth_b.h)
  bool linear_driver = false;     // supply sag of a linear driver (else a PWM bridge)
  double restitution = 0.2;       // backlash impacts
  double rail_c = 470e-6;         // supply rail capacitor, F
  // pulse train with frames (frame_s > 0): the pulse is 1.5 ms + this x (sp -
  // 90 deg) wide and decoded at its falling edge, s/deg
  double pulse_s_per_deg = 0;
  // measurement
  double angle_noise_deg = 0.2, angle_lsb_deg = 180.0 / 1023, current_noise_a = 0.002, current_full_a = 0.5;
  double base_spread = 0.05;  // true Kp, Km=Kt, R, Jl = datasheet x (1 +- U(spread))
  double sample_hz = 1000;    // mean sample rate
  double jitter = 0;          // sample times jitter by +-jitter of the interval (uniform)
  bool current_column = true; // the record has current_a
  bool exact = false;         // the meter adds no noise and does not quantise (the study's effect sizes)
};

// the recording conditions of a study seed: noise level (3), load inertia
// (2), sample rate (log-uniform 200 Hz..2 kHz) with +-20 % timestamp jitter,
// and one record in four without the current column
struct Conditions {
  int noise = 1;          // 0, 1, 2: 0.1 / 0.2 / 0.4 deg and 1 / 2 / 4 mA
  double jl = 3e-6;       // 3e-6 or 2e-5 kg m^2
  double sample_hz = 1000;
  double jitter = 0.2;
  bool current = true;
};

inline Conditions conditions(unsigned seed) {
  std::mt19937_64 rng(0x5eed0000u + seed);
  std::uniform_real_distribution<double> u(0, 1);
  Conditions c;
  c.noise = static_cast<int>(seed % 3);
  c.jl = (seed / 3) % 2 ? 2e-5 : 3e-6;
  c.sample_hz = 200.0 * std::pow(10.0, u(rng));
  c.current = seed % 4 != 3;
  return c;
}

// the plain conditions of the ctest cases and the old study: 1 kHz, no jitter
inline Conditions plain_conditions() {
  Conditions c;
  c.jitter = 0;
  return c;
}

inline void apply(const Conditions& c, Truth* t) {
  const double f = c.noise == 0 ? 0.5 : c.noise == 1 ? 1.0 : 2.0;
  t->angle_noise_deg = 0.2 * f;
  t->current_noise_a = 0.002 * f;
  t->jl = c.jl;
  t->sample_hz = c.sample_hz;
  t->jitter = c.jitter;
  t->current_column = c.current;
}

struct Series {
  std::vector<double> t, sp, angle, current;
  bool has_current = true;
};

// the set-point program, 4 s: big moves, small moves, reversals, holds
inline std::vector<std::pair<double, double>> program() {
  return {{0.0, 30},   {0.107, 120}, {0.462, 100}, {0.719, 104}, {0.955, 60},  {1.314, 63}, {1.561, 58}, {1.806, 110},
          {2.153, 90}, {2.417, 93},  {2.668, 140}, {3.002, 135}, {3.259, 80},  {3.611, 84}, {3.866, 70}};
}

// sample times (mean rate, jitter) on a grid of `quantum` seconds, strictly
// increasing, from 0 to duration
inline std::vector<double> sample_times(const Truth& tr, double duration, double quantum, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-tr.jitter, tr.jitter);
  const double dt = 1.0 / tr.sample_hz;
  std::vector<double> t = {0.0};
  for (long k = 1;; ++k) {
    double tk = std::round((k + u(rng)) * dt / quantum) * quantum;
    if (tk > duration + 1e-12) break;
    if (tk <= t.back() + 0.5 * quantum) tk = t.back() + quantum;
    t.push_back(tk);
  }
  return t;
}

// the set-point at each sample: a program change acts from the first sample
// at or after its time (the bench commands on its sampling clock)
inline std::vector<double> sampled_program(const std::vector<double>& t) {
  const auto prog = program();
  std::vector<double> sp(t.size());
  size_t p = 0;
  for (size_t k = 0; k < t.size(); ++k) {
    while (p + 1 < prog.size() && prog[p + 1].first <= t[k] + 1e-12) ++p;
    sp[k] = prog[p].second;
  }
  return sp;
}

// the measurement chain: pot noise + 10-bit quantisation, current noise + 10-bit ADC
struct Meter {
  const Truth& tr;
  std::normal_distribution<double> na, ni;
  explicit Meter(const Truth& t) : tr(t), na(0, t.angle_noise_deg), ni(0, t.current_noise_a) {}
  // (exact: the noise is drawn all the same, so that the rest of the record
  // sees the same random numbers)
  double angle(double deg, std::mt19937_64& rng) {
    const double n = na(rng);
    return tr.exact ? deg : std::round((deg + n) / tr.angle_lsb_deg) * tr.angle_lsb_deg;
  }
  double current(double a, std::mt19937_64& rng) {
    const double n = ni(rng);
    if (tr.exact) return a;
    const double c = std::clamp(std::round((a + n) / tr.current_full_a * 1023), 0.0, 1023.0);
    return c * tr.current_full_a / 1023;
  }
  // the sd of what the meter adds: the noise and the quantisation's (lsb / sqrt 12)
  double angle_sd() const { return std::hypot(tr.angle_noise_deg, tr.angle_lsb_deg / std::sqrt(12.0)); }
  double current_sd() const { return std::hypot(tr.current_noise_a, tr.current_full_a / 1023 / std::sqrt(12.0)); }
};

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
  std::fprintf(f, s.has_current ? "t_s,setpoint_deg,angle_deg,current_a\n" : "t_s,setpoint_deg,angle_deg\n");
  for (size_t k = 0; k < s.t.size(); ++k) {
    std::fprintf(f, "%.6f,%.3f,%.4f", s.t[k], s.sp[k], s.angle[k]);
    if (s.has_current) std::fprintf(f, ",%.6f", s.current[k]);
    std::fprintf(f, "\n");
  }
  return std::fclose(f) == 0;
}

}  // namespace synth
