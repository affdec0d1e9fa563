// Generator C (synth_c.h), the held-out generator: its physics piece by
// piece (the gear's play between two inertias, LuGre's steady friction, the
// ADC, the pulse train's decoding, the coloured noise), its determinism, and
// `chainsim calibrate` run on two of its records (the study has them all:
// calibration_study --generator c, docs/calibration.md "Held-out judgement").
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <set>

#include "common.h"
#include "synth_c.h"

namespace {

using synth_c::kDeg;

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// the rotor crosses the play alone: the output does not move until the
// play is closed, then they turn together, the mesh deflected by little
TEST(GeneratorC, BacklashIsAGapBetweenTwoInertias) {
  synth_c::Servo s;
  s.g = 1.5 * kDeg;   // 3 deg of play, the rotor in its middle
  s.c_mesh = 2 * 0.4 * std::sqrt(s.k_mesh * s.j * s.jl / (s.j + s.jl));
  synth_c::State x = {0, 0, 0, 0, 0, 0, 0, 0, s.vs};
  const double ref = 30 * kDeg;
  double t = 0, closed_at = -1;
  while (t < 0.05) {
    synth_c::advance(s, ref, x, t, t + 1e-5);
    t += 1e-5;
    const double d = x[1] - x[3];
    if (closed_at < 0 && std::fabs(d) > s.g) closed_at = t;
    if (closed_at < 0) {
      EXPECT_EQ(x[3], 0.0) << "the output moved inside the play at " << t;
      EXPECT_EQ(x[4], 0.0);
    }
  }
  ASSERT_GT(closed_at, 0.0);
  EXPECT_LT(closed_at, 0.01);
  EXPECT_GT(x[3], 5 * kDeg);   // turned together after
  EXPECT_LT(std::fabs(x[1] - x[3]), s.g + 0.2 * kDeg);
}

// at a constant speed the bristles settle where LuGre's friction is the
// Stribeck curve sign(v) (Fc + (Fs - Fc) exp(-(v/vs)^2))
TEST(GeneratorC, LugreSteadyFrictionIsTheStribeckCurve) {
  const synth_c::Lugre f = synth_c::lugre(0.004, 0.006, 0.02, 3e-6);
  for (double v : {-0.5, -0.02, -0.005, 0.001, 0.01, 0.03, 0.2, 3.0}) {
    // at a fixed speed over 30 times the bristles' deflection at the static level
    double z = 0;
    const double h = 30 * 0.01 * kDeg / std::fabs(v) / 200000;
    for (int k = 0; k < 200000; ++k) z += h * f.dz(v, z);
    const double stribeck = (v > 0 ? 1 : -1) * (0.004 + 0.002 * std::exp(-(v / 0.02) * (v / 0.02)));
    EXPECT_NEAR(f.torque(v, z), stribeck, 1e-6 * 0.006) << "v " << v;
    EXPECT_NEAR(f.steady(v), stribeck, 1e-15) << "v " << v;
  }
  // at rest, below the static level, the bristles hold (presliding): a
  // deflection of 0.01 deg carries the static level
  EXPECT_NEAR(f.s0 * 0.01 * kDeg, 0.006, 1e-12);
  EXPECT_EQ(synth_c::Lugre{}.torque(1.0, 0.3), 0.0);   // off
}

// the 10-bit ADC: codes an lsb apart, within half an lsb, clamped to its span
TEST(GeneratorC, AdcQuantisesToTenBits) {
  const double lsb = 200.0 / 1024, lo = -10;
  std::set<double> levels;
  for (double v = 0; v <= 20; v += 0.001) {
    const double q = synth_c::adc(v, lsb, lo);
    EXPECT_LE(std::fabs(q - v), 0.5 * lsb + 1e-12);
    levels.insert(q);
  }
  for (auto a = levels.begin(), b = std::next(a); b != levels.end(); ++a, ++b) EXPECT_NEAR(*b - *a, lsb, 1e-9);
  EXPECT_EQ(synth_c::adc(-50, lsb, lo), lo);
  EXPECT_EQ(synth_c::adc(500, lsb, lo), lo + 1023 * lsb);
  // a record's angles are on the grid
  const synth_c::Case c = synth_c::case_named("C: null");
  const synth_c::Truth tr = synth_c::truth(c, 900);
  const synth_c::Record r = synth_c::generate(tr, 900);
  for (double a : r.angle) {
    const double code = (a - lo) / lsb;
    EXPECT_NEAR(code, std::round(code), 1e-6);
  }
}

// the pulse train: a set-point change reaches the servo when the first
// pulse that carries it ends (the frame's rising edge at phase + n T, plus
// the pulse's width), so the output holds until then
TEST(GeneratorC, PulseTrainDecodesAtTheFallingEdge) {
  EXPECT_DOUBLE_EQ(synth_c::pulse_width_s(90), 1.5e-3);
  EXPECT_DOUBLE_EQ(synth_c::pulse_width_s(0), 0.5e-3);
  EXPECT_DOUBLE_EQ(synth_c::pulse_width_s(180), 2.5e-3);
  synth_c::Case c = synth_c::case_named("C: pwm_frame_delay");
  bool checked = false;
  for (unsigned seed = 900; seed < 910 && !checked; ++seed) {
    synth_c::Truth tr = synth_c::truth(c, seed);
    if (tr.cond.sample_hz < 400 || tr.cond.profile == 2) continue;   // a fast record of steps
    tr.meter.exact = true;
    const synth_c::Record r = synth_c::generate(tr, seed);
    const double period = tr.servo.frame_s, phase = tr.servo.frame_phase_s;
    ASSERT_GT(period, 0.0);
    for (size_t k = 1; k + 1 < r.t.size(); ++k) {
      if (std::fabs(r.sp[k] - r.sp[k - 1]) < 20) continue;   // a big move
      const double n = std::ceil((r.t[k] - phase) / period - 1e-12);
      const double decoded = phase + n * period + synth_c::pulse_width_s(r.sp[k]);
      for (size_t q = k; q < r.t.size() && r.t[q] < decoded; ++q)
        EXPECT_NEAR(r.angle[q], r.angle[k - 1], 1e-3) << "seed " << seed << ": moved before its pulse was decoded";
      size_t after = k;
      while (after < r.t.size() && r.t[after] < decoded + 0.01) ++after;
      ASSERT_LT(after, r.t.size());
      EXPECT_GT(std::fabs(r.angle[after] - r.angle[k - 1]), 1.0) << "seed " << seed << ": not moving 10 ms after";
      checked = true;
    }
  }
  EXPECT_TRUE(checked);
  // the phase against the set-point changes is random over the frame
  std::set<long> phases;
  for (unsigned seed = 900; seed < 910; ++seed) {
    const synth_c::Truth tr = synth_c::truth(c, seed);
    EXPECT_GE(tr.servo.frame_phase_s, 0.0);
    EXPECT_LT(tr.servo.frame_phase_s, tr.servo.frame_s);
    phases.insert(std::lround(tr.servo.frame_phase_s / tr.servo.frame_s * 4));
  }
  EXPECT_GE(phases.size(), 3u);
}

// first-order filtered noise: its sd, and successive samples correlated by exp(-dt / tau)
TEST(GeneratorC, ColouredNoiseHasItsSdAndCorrelation) {
  std::vector<double> t;
  for (int k = 0; k < 200000; ++k) t.push_back(k * 1e-3);
  std::mt19937_64 rng(7);
  const std::vector<double> x = synth_c::coloured_noise(t, 0.3, 0.01, rng);
  double ss = 0, sc = 0;
  for (size_t k = 0; k < x.size(); ++k) {
    ss += x[k] * x[k];
    if (k) sc += x[k] * x[k - 1];
  }
  EXPECT_NEAR(std::sqrt(ss / x.size()), 0.3, 0.01);
  EXPECT_NEAR(sc / ss, std::exp(-0.1), 0.01);
}

// a current limit: a stalled servo draws the limit (plus what the sense
// amplifier lets through), not the supply's stall current
TEST(GeneratorC, CurrentLimitHoldsAStall) {
  synth_c::Servo s;
  s.ilim = 0.15;
  s.jl = 1e3;   // the output held
  synth_c::State x = {0, 0, 0, 0, 0, 0, 0, 0, s.vs};
  synth_c::advance(s, 60 * kDeg, x, 0, 0.05);
  EXPECT_GT(x[0], 0.15);
  EXPECT_LT(x[0], 0.15 + s.vs / s.k_ilim);
  s.ilim = 0;
  x = {0, 0, 0, 0, 0, 0, 0, 0, s.vs};
  synth_c::advance(s, 60 * kDeg, x, 0, 0.05);
  EXPECT_NEAR(x[0], s.vs / s.r, 0.01);
}

// same seed, same bytes; another seed, another record
TEST(GeneratorC, SameSeedSameFiles) {
  const synth_c::Case c = synth_c::case_named("C: backlash+supply_sag");
  const std::string a = synth::make_temp_dir(), b = synth::make_temp_dir();
  synth_c::write_case(c, 903, a);
  synth_c::write_case(c, 903, b);
  for (const char* f : {"/bench.yaml", "/m.csv", "/truth.json"}) EXPECT_EQ(read_all(a + f), read_all(b + f)) << f;
  synth_c::write_case(c, 904, b);
  EXPECT_NE(read_all(a + "/m.csv"), read_all(b + "/m.csv"));
  std::filesystem::remove_all(a);
  std::filesystem::remove_all(b);
}

// the record's truth: an effect is expected when the record shows it, and
// its size there is 0 when the servo lacks it
TEST(GeneratorC, PerfectAnswer) {
  const synth_c::Answer null = synth_c::perfect_answer(synth_c::case_named("C: null"), 900);
  EXPECT_EQ(null.verdict, "no_missing_effect");
  EXPECT_TRUE(null.expect.empty());
  EXPECT_EQ(null.weakest, -1.0);
  const synth_c::Case bl = synth_c::case_named("C: backlash");
  EXPECT_EQ(synth_c::effect_size(bl, 900, "deadband"), 0.0);
  const synth_c::Answer a = synth_c::perfect_answer(bl, 900);
  EXPECT_GT(a.weakest, synth_c::kShown);
  EXPECT_EQ(a.verdict, "explained");
  EXPECT_EQ(a.expect, std::vector<std::string>{"backlash"});
  const synth_c::Answer o = synth_c::perfect_answer(synth_c::case_named("C: return spring (outside the catalogue)"), 900);
  EXPECT_EQ(o.verdict, "unexplained");
  EXPECT_TRUE(o.expect.empty());
}

// calibrate on generator C's records: they are read, and the null is called
// so (the held-out study judges the rest, never tuned on)
TEST(GeneratorC, CalibrateReadsItsRecords) {
  for (const char* name : {"C: null", "C: deadband"}) {
    const synth_c::Case c = synth_c::case_named(name);
    ASSERT_FALSE(c.name.empty()) << name;
    const std::string dir = synth::make_temp_dir();
    const synth_c::Answer a = synth_c::write_case(c, 900, dir);
    const synth::Outcome o = synth::calibrate_files(dir);
    EXPECT_EQ(o.exit_code, 0) << name;
    ASSERT_TRUE(o.report.is_object()) << name;
    std::string found;
    for (const auto& n : o.names) found += " " + n;
    std::printf("%s seed 900: truth %s; calibrate %s%s (%.1f s CPU)\n", name, a.verdict.c_str(),
                o.report["verdict"].get<std::string>().c_str(), found.c_str(), o.cpu_s);
    if (c.hidden.empty()) {
      EXPECT_EQ(o.report["verdict"], "no_missing_effect");
    }
    std::filesystem::remove_all(dir);
  }
}

}  // namespace
