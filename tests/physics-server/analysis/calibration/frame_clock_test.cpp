// The frame clock: period and phase from the delays of set-point changes,
// first on delays made from a known clock, then on a record of the bench
// model whose servo reads its set-point at 20 ms frames starting 7 ms in.
#include "analysis/calibration/frame_clock.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>

#include "analysis/calibration/effect_catalogue.h"
#include "analysis/calibration/effect_search.h"
#include "analysis/calibration/paired_runs.h"
#include "analysis/calibration/servo_fit.h"
#include "bench_record.h"

namespace chainsim {
namespace {

// fmod_exact and wrap_to_period give std::fmod's bits, on the scan's own
// kind of arguments (frame times less change times, periods of 1-50 ms, the
// quotient from the frequency) and on the hard ones: near-multiples and
// their neighbours (where x / p rounds to the next integer), p's own
// neighbour below (r + p rounds to 2p), negative values, zeros of both
// signs, subnormal x, tiny and subnormal periods, quotients about 2^52 and
// beyond, inverses that are off (so that the quotient is off), and periods
// wrap_to_period must refuse (zero, negative, NaN, huge). Both of
// fmod_exact's ways are taken, many times each
TEST(FrameClock, TheFastRemainderIsFmodBitForBit) {
  auto bits = [](double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  // which of fmod_exact's ways an argument takes
  auto fast = [](double x, double p, double p_inv) {
    double r;
    return fmod_by_fma(x, p, p_inv, r);
  };
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> ux(-12.0, 12.0), up(1e-3, 50e-3);
  std::uniform_int_distribution<int> un(-4000, 4000), uk(-3, 3);
  long checked = 0, fast_way = 0, long_way = 0;
  for (int i = 0; i < 100000; ++i) {
    double p = up(rng);
    if (i % 100 == 1) p *= 1e-300;                  // tiny: 1 / p overflows
    if (i % 100 == 2) p = 4.9e-324 * (1 + i % 7);   // subnormal
    const double m = un(rng) * p;
    std::vector<double> xs = {ux(rng),
                              m,
                              std::nextafter(m, 1e300),
                              std::nextafter(m, -1e300),
                              std::nextafter(p, 0.0),
                              -std::nextafter(p, 0.0),
                              0.0,
                              -0.0,
                              ux(rng) * 1e-310,
                              (0x1p52 + uk(rng)) * p,
                              1e17 * ux(rng)};
    // the scan's inverse: the frequency the period was made from (p_f its
    // period); and inverses that are off
    const double f = 1.0 / p, p_f = 1.0 / f;
    const std::vector<double> p_invs = {f, f * (1 + 1e-9), f * (1 - 1e-3), f * (1 + 1e-3), 2 * f, 0.0};
    for (double x : xs) {
      ASSERT_EQ(bits(fmod_exact(x, p)), bits(std::fmod(x, p))) << x << " " << p;
      ASSERT_EQ(bits(wrap_to_period(x, p)), bits(std::fmod(std::fmod(x, p) + p, p))) << x << " " << p;
      ASSERT_EQ(bits(wrap_to_period(x, p_f, f)), bits(std::fmod(std::fmod(x, p_f) + p_f, p_f))) << x << " " << p_f;
      for (double pi : p_invs) {
        ASSERT_EQ(bits(fmod_exact(x, p, pi)), bits(std::fmod(x, p))) << x << " " << p << " " << pi;
        ASSERT_EQ(bits(wrap_to_period(x, p, pi)), bits(std::fmod(std::fmod(x, p) + p, p))) << x << " " << p << " " << pi;
        ++(fast(x, p, pi) ? fast_way : long_way);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 100000L * 11 * 6);
  EXPECT_GT(fast_way, 1000000);
  EXPECT_GT(long_way, 1000000);
  // periods wrap_to_period leaves to fmod: the same bits (NaN: a NaN)
  for (double p : {0.0, -0.02, -5e-324, 1e308, std::nan("")}) {
    const double ref = std::fmod(std::fmod(1.234, p) + p, p);
    if (std::isnan(ref)) EXPECT_TRUE(std::isnan(wrap_to_period(1.234, p, 1.0 / p))) << p;
    else EXPECT_EQ(bits(wrap_to_period(1.234, p, 1.0 / p)), bits(ref)) << p;
  }
}

// 15 changes at random times over 4 s, delayed by the clock, plus noise
std::vector<ChangeDelay> delays_of(const FrameClock& c, double t0, double noise, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.05, 4.0);
  std::normal_distribution<double> n(0, noise);
  std::vector<double> t(15);
  for (double& x : t) x = t0 + u(rng);
  std::sort(t.begin(), t.end());
  std::vector<ChangeDelay> d;
  for (double x : t) d.push_back({x, std::max(0.0, frame_delay(c, t0, x) + n(rng)), std::max(noise, 1e-4)});
  return d;
}

// the datasheet with pwm frames of the period, starting at the phase
BenchConfig framed(double period_s, double phase_s) {
  BenchConfig b = test_datasheet();
  b.servo.pwm_frame_s = period_s;
  b.servo.pwm_frame_phase_s = phase_s;
  return b;
}

// a bench-model record of truth (0.2 deg, 2 mA of noise) against the
// datasheet, the loss's unit that noise in normalised units
FitProblem problem_of(const BenchConfig& truth, unsigned seed) {
  FitProblem p = make_fit_problem(test_datasheet(), bench_record(truth, seed));
  p.noise.angle = 0.2 / p.sa;
  p.noise.current = 0.002 / p.si;
  return p;
}

TEST(FrameClock, DelayIsTheTimeToTheNextFrame) {
  const FrameClock c{0.02, 0.007};
  EXPECT_NEAR(frame_delay(c, 1.0, 1.0), 0.007, 1e-12);
  EXPECT_NEAR(frame_delay(c, 1.0, 1.008), 0.019, 1e-12);
  EXPECT_NEAR(frame_delay(c, 1.0, 1.027), 0.0, 1e-12);
  EXPECT_NEAR(frame_delay(c, 1.0, 2.5), 0.007, 1e-9);   // 1.507 + 0.02 k
}

// two clocks are one when every frame of the record is within the
// tolerance of the other's: across the phase's wrap, and not when the period
// drifts the frames apart by the record's end
TEST(FrameClock, SameFramesWithinTheToleranceOverTheWholeRecord) {
  const FrameClock a{0.015, 0.0140};
  EXPECT_TRUE(same_frames(a, a, 4.0, 0.5e-3));
  EXPECT_TRUE(same_frames(a, FrameClock{0.015, 0.0143}, 4.0, 0.5e-3));
  EXPECT_FALSE(same_frames(a, FrameClock{0.015, 0.0150}, 4.0, 0.5e-3));
  // frames at 0.2, 15.2 ms: 1.2 ms after a's at 14.0, 29.0 ms
  EXPECT_FALSE(same_frames(a, FrameClock{0.015, 0.0002}, 4.0, 0.5e-3));
  // 14.9 ms and 0.1 ms are 0.2 ms apart across the wrap
  EXPECT_TRUE(same_frames(FrameClock{0.015, 0.0149}, FrameClock{0.015, 0.0001}, 4.0, 0.5e-3));
  // 2 us more per frame: 267 frames in 4 s drift 0.53 ms apart, 80 in 1.2 s do not
  const FrameClock b{0.015002, 0.0140};
  EXPECT_FALSE(same_frames(a, b, 4.0, 0.5e-3));
  EXPECT_TRUE(same_frames(a, b, 1.2, 0.5e-3));
  EXPECT_FALSE(same_frames(a, FrameClock{}, 4.0, 0.5e-3));
}

TEST(FrameClock, RecoversPeriodAndPhaseFromNoisyDelays) {
  int runs = 0, missed = 0;   // 95 % period intervals that miss the truth
  for (const FrameClock truth : {FrameClock{0.02, 0.007}, FrameClock{0.0123, 0.0111}, FrameClock{0.0035, 0.001}}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const double t0 = 0.25;
      const FrameClockFit f = fit_frame_clock(delays_of(truth, t0, 2e-4, seed), t0, 2.5e-3, 40e-3);
      ASSERT_TRUE(f.found) << truth.period_s << " seed " << seed;
      EXPECT_NEAR(f.clock.period_s, truth.period_s, 2e-5) << seed;
      // phases compare modulo the period
      const double dp = std::fmod(f.clock.phase_s - truth.phase_s + 1.5 * truth.period_s, truth.period_s) -
                        0.5 * truth.period_s;
      EXPECT_NEAR(dp, 0.0, 6e-4) << seed;
      ++runs;
      missed += f.period_ci_s.first > truth.period_s || f.period_ci_s.second < truth.period_s;
      EXPECT_GE(f.inliers, 12);
    }
  }
  // a 95 % interval misses about 1 in 20; 3 or more of 15 would happen by
  // chance 3.6 % of the time
  std::printf("period intervals missing the truth: %d of %d\n", missed, runs);
  EXPECT_LE(missed, 2);
}

TEST(FrameClock, NeitherHalfNorTwiceThePeriod) {
  // 40 ms frames: 20 ms would predict half the delays too short, 80 ms
  // half of them a frame too late
  const FrameClock truth{0.04, 0.013};
  const FrameClockFit f = fit_frame_clock(delays_of(truth, 0.0, 1e-4, 3), 0.0, 2.5e-3, 40e-3);
  ASSERT_TRUE(f.found);
  EXPECT_NEAR(f.clock.period_s, 0.04, 1e-4);
  // outliers (a change the model got wrong) do not move it
  std::vector<ChangeDelay> d = delays_of(truth, 0.0, 1e-4, 4);
  d[3].delay += 0.011, d[9].delay = 0.0;
  const FrameClockFit g = fit_frame_clock(d, 0.0, 2.5e-3, 40e-3);
  ASSERT_TRUE(g.found);
  EXPECT_NEAR(g.clock.period_s, 0.04, 1e-4);
  EXPECT_EQ(g.inliers, 13);
  // too few changes tell their delay
  d.resize(3);
  EXPECT_FALSE(fit_frame_clock(d, 0.0, 2.5e-3, 40e-3).found);
}

// a falling-edge decoder: each change waits for the next frame, then for
// its pulse, 1.5 ms + k (sp - 90 deg) wide. With set-points over 10-170
// degrees and k = 11.1 us/deg the pulses spread the delays over 1.8 ms, more
// than the scan's tolerance: the delays as measured make no clock, or one
// that explains fewer changes; less each change's pulse width they make the
// frames' clock, every change explained
TEST(FrameClock, PulseWidthsSpreadTheDelaysTheirCorrectionGathersThem) {
  const FrameClock truth{0.018, 0.0042};
  const double k = 11.1e-6, t0 = 0.1;
  int plain_found = 0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::vector<ChangeDelay> d = delays_of(truth, t0, 1e-4, seed);
    std::mt19937_64 rng(100 + seed);
    std::uniform_real_distribution<double> sp(10.0, 170.0);
    for (ChangeDelay& c : d) {
      c.sp_deg = sp(rng);
      c.delay += 1.5e-3 + k * (c.sp_deg - 90.0);
    }
    const FrameClockFit plain = fit_frame_clock(d, t0, 2.5e-3, 40e-3);
    plain_found += plain.found;
    const std::vector<ChangeDelay> fe = falling_edge_delays(d, k);
    ASSERT_EQ(fe.size(), d.size());
    EXPECT_NEAR(fe[2].delay + fe[2].shift, d[2].delay, 1e-15);   // the measured delay is kept
    const FrameClockFit f = fit_frame_clock(fe, t0, 2.5e-3, 40e-3);
    ASSERT_TRUE(f.found) << seed;
    EXPECT_EQ(f.inliers, static_cast<int>(d.size())) << seed;
    if (plain.found) {
      EXPECT_LT(plain.inliers, f.inliers) << seed;
    }
    EXPECT_NEAR(f.clock.period_s, truth.period_s, 2e-5) << seed;
    EXPECT_NEAR(std::remainder(f.clock.phase_s - truth.phase_s, truth.period_s), 0.0, 6e-4) << seed;
    // the wrong slope leaves a spread: fewer changes explained
    const FrameClockFit w = fit_frame_clock(falling_edge_delays(d, 0.25 * k), t0, 2.5e-3, 40e-3);
    if (w.found) {
      EXPECT_LT(w.inliers, f.inliers) << seed;
    }
  }
  std::printf("a plain clock found in %d of 5\n", plain_found);
}

// two of three changes are small steps whose delays an effect the model
// lacks has scrambled (as a deadband does to a 3-5 degree step: off by
// milliseconds with a narrow curvature): from every change no clock agrees
// with half of them; from the steps of kClockMinStepDeg or more, the truth
TEST(FrameClock, LargeStepsAloneWhereSmallStepsAreScrambled) {
  const FrameClock truth{0.0125, 0.0006};
  std::vector<ChangeDelay> d = delays_of(truth, 0.0, 1e-4, 5);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> any(0.0, 0.012);
  for (size_t c = 0; c < d.size(); ++c) {
    const bool small = c % 3 != 0;
    d[c].step_deg = small ? -4.0 : 40.0;
    if (small) d[c].delay = any(rng);
  }
  const FrameClockFit all = fit_frame_clock(d, 0.0, 2.5e-3, 40e-3);
  EXPECT_FALSE(all.found && std::fabs(all.clock.period_s - truth.period_s) < 1e-4)
      << "from every change: " << all.clock.period_s;
  const FrameClockFit large = fit_frame_clock(d, 0.0, 2.5e-3, 40e-3, kClockMinStepDeg);
  ASSERT_TRUE(large.found);
  EXPECT_EQ(large.used, 5);
  EXPECT_NEAR(large.clock.period_s, truth.period_s, 1e-4);
}

TEST(FrameClock, FromABenchRecordWithFramesAtAnArbitraryPhase) {
  ModelRuns runs;
  FitProblem p = problem_of(framed(0.02, 0.007), 3);
  const std::vector<ChangeDelay> d = estimate_delays(runs, p, test_datasheet(), 0.04);
  ASSERT_EQ(d.size(), 14u);
  int told = 0;
  for (const ChangeDelay& c : d) {
    if (c.sd < 0 || c.sd > 2e-3) continue;
    ++told;
    const double truth_delay = frame_delay({0.02, 0.007}, 0.0, c.t);
    EXPECT_NEAR(c.delay, truth_delay, 1e-3) << "change at " << c.t;
  }
  EXPECT_GE(told, 10);
  const FrameClockFit f = frame_clock_for(runs, p, test_datasheet());
  ASSERT_TRUE(f.found);
  std::printf("bench record, 20 ms frames at 7 ms: period %.4f ms [%.4f, %.4f], phase %.3f ms [%.3f, %.3f], %d of %d "
              "changes\n",
              f.clock.period_s * 1e3, f.period_ci_s.first * 1e3, f.period_ci_s.second * 1e3, f.clock.phase_s * 1e3,
              f.phase_ci_s.first * 1e3, f.phase_ci_s.second * 1e3, f.inliers, f.used);
  EXPECT_NEAR(f.clock.period_s, 0.02, 5e-5);
  EXPECT_NEAR(f.clock.phase_s, 0.007, 5e-4);
}

// a deadband the model lacks bends the model's timing: measured against the
// datasheet, several changes' delays are a millisecond or more off the
// frames', but those changes do not fit the model to the noise either, and
// their sd says so; with the sd from the curvature alone a clock of 15.6 ms
// matched half of the changes (the truth's is 22.4 ms)
TEST(FrameClock, FoundThroughADeadbandTheModelLacks) {
  ModelRuns runs;
  BenchConfig truth = framed(0.0224, 0.016);
  truth.servo.deadband_deg = 3.0;
  FitProblem p = problem_of(truth, 7);
  const std::vector<ChangeDelay> d = estimate_delays(runs, p, test_datasheet(), 0.04);
  int off = 0, off_within_sd = 0;   // changes 0.5 ms or more off the truth; of those, within 2.5 sd
  for (const ChangeDelay& c : d) {
    if (c.sd < 0) continue;
    const double err = std::fabs(c.delay - frame_delay({0.0224, 0.016}, 0.0, c.t));
    if (err < 5e-4) continue;
    ++off;
    off_within_sd += err < 2.5 * c.sd;
  }
  const FrameClockFit f = frame_clock_for(runs, p, test_datasheet());
  std::printf("deadband 3 deg, 22.4 ms frames at 16 ms: %d changes 0.5 ms or more off, %d of them within 2.5 sd; "
              "period %.4f ms, phase %.3f ms, %d of %d changes\n",
              off, off_within_sd, f.clock.period_s * 1e3, f.clock.phase_s * 1e3, f.inliers, f.used);
  EXPECT_GE(off, 3);
  EXPECT_GE(off_within_sd, 2);
  ASSERT_TRUE(f.found);
  EXPECT_NEAR(f.clock.period_s, 0.0224, 2e-4);
  const double dp = std::fmod(f.clock.phase_s - 0.016 + 1.5 * 0.0224, 0.0224) - 0.5 * 0.0224;
  EXPECT_NEAR(dp, 0.0, 1e-3);
}

// a clock found while another effect was missing carries that effect's
// timing in its delays; once the other effect is in the model the clock is
// fitted again on top of it (the search does this in each round's reference)
TEST(FrameClock, FittedAgainOnTopOfTheOtherEffects) {
  ModelRuns runs;
  BenchConfig truth = framed(0.02, 0.007);
  truth.servo.current_limit_a = 0.2;
  FitProblem p = problem_of(truth, 5);
  const int pwm = effect_variants("pwm_frame_delay").at(0), limit = effect_variants("current_limit").at(0);
  // the clock 0.3 ms long and 2 ms early, found first; the limit found after it
  const std::vector<double> off = {1, 1, 1, 1, 20.3, 5.0, 0.2};
  const Fit f = evaluate_fit(runs, p, {pwm, limit}, off);
  const Fit g = refit_frame_clock(runs, p, f);
  ASSERT_EQ(g.effects, f.effects);
  ASSERT_EQ(g.x.size(), off.size());
  std::printf("clock fitted again: period %.4f ms, phase %.3f ms, limit %.4f A; training loss %.4g -> %.4g\n",
              g.x[4], g.x[5], g.x[6], f.train, g.train);
  EXPECT_LT(g.train, 0.5 * f.train);
  EXPECT_NEAR(g.x[4], 20.0, 0.05);
  EXPECT_NEAR(g.x[5], 7.0, 0.5);
  EXPECT_NEAR(g.x[6], 0.2, 0.02);   // the other effect's value stays in its place
  ASSERT_EQ(g.held_ci.size(), g.x.size());
  EXPECT_LE(g.held_ci[4].first, g.x[4]);
  EXPECT_GE(g.held_ci[4].second, g.x[4]);
  // a clock found last was fitted on top of everything already
  const Fit h = evaluate_fit(runs, p, {limit, pwm}, {1, 1, 1, 1, 0.2, 20.3, 5.0});
  EXPECT_EQ(refit_frame_clock(runs, p, h).x, h.x);
}

// a falling-edge solution on a record of plain frames (20 ms at 7 ms): the
// plain clock fitted again from it latches where the falling edge of the
// mean set-point's pulse fell (its frames moved later by that pulse, 1.5 ms
// + k (mean sp - 90 deg)), and so finds the truth's frames, the slope
// dropped and the other parameters in their places
TEST(FrameClock, ThePlainClockFittedAgainFromAFallingEdgeSolution) {
  ModelRuns runs;
  const FitProblem p = problem_of(framed(0.02, 0.007), 3);
  const std::vector<int> forms = effect_variants("pwm_frame_delay");
  const int plain = forms.at(0), falling = forms.at(1);
  ASSERT_STREQ(effect_catalogue()[falling].refines, effect_catalogue()[plain].variant);
  const std::vector<double> base = {1, 1, 1, 1};
  const Fit ref = evaluate_fit(runs, p, {}, base);
  double mean_sp = 0;
  const std::vector<SetpointChange> ch = setpoint_changes(p.m);
  for (const SetpointChange& c : ch) mean_sp += p.m.sp[c.k];
  mean_sp /= static_cast<double>(ch.size());
  const double k = 8.0, pulse_ms = 1.5 + 1e-3 * k * (mean_sp - 90.0);
  std::vector<double> x = base;
  x.insert(x.end(), {20.0, 7.0 - pulse_ms, k});
  Fit fe = evaluate_fit(runs, p, {falling}, x);
  fe.held_ci.assign(x.size(), {0.0, 0.0});
  fe.held_ci[kNumBase] = {19.99, 20.01};
  fe.held_ci[kNumBase + 1] = {x[kNumBase + 1] - 0.1, x[kNumBase + 1] + 0.1};
  const Fit g = refit_plain_clock(runs, p, ref, plain, fe);
  std::printf("from a falling-edge solution (k %.1f us/deg, mean pulse %.3f ms): clock %.4f ms at %.3f ms, "
              "training loss %.4g -> %.4g\n",
              k, pulse_ms, g.x[kNumBase], g.x[kNumBase + 1], fe.train, g.train);
  ASSERT_EQ(g.effects, std::vector<int>{plain});
  ASSERT_EQ(g.x.size(), kNumBase + 2);
  EXPECT_NEAR(g.x[kNumBase], 20.0, 0.05);
  EXPECT_NEAR(g.x[kNumBase + 1], 7.0, 0.5);
  EXPECT_LT(g.train, fe.train);
  ASSERT_EQ(g.held_ci.size(), g.x.size());
  // the clock's intervals are about the refitted values, at least the
  // falling-edge fit's widths
  for (size_t i : {kNumBase, kNumBase + 1}) {
    EXPECT_LE(g.held_ci[i].first, g.x[i]) << i;
    EXPECT_GE(g.held_ci[i].second, g.x[i]) << i;
    EXPECT_GE(g.held_ci[i].second - g.held_ci[i].first, fe.held_ci[i].second - fe.held_ci[i].first - 1e-12) << i;
  }
  EXPECT_NEAR(0.5 * (g.held_ci[kNumBase + 1].first + g.held_ci[kNumBase + 1].second), g.x[kNumBase + 1], 1e-9);
}

// the screen (effect_search.h, screen_for) watches every clock found, each in
// its own first fit: a record with frames fits its clock exactly as without
// the screen; a record without frames, of a Coulomb friction the reference
// holds, where the datasheet start's delays show a clock that is not there
// (the reference's show none), stops it after the screen's runs, where
// fitted in full it ends worse than the reference
TEST(FrameClock, TheScreenStopsEachClockThatDoesNotGain) {
  ModelRuns runs;
  const int pwm = effect_variants("pwm_frame_delay").at(0);
  const std::vector<double> base = {1.1, 0.9, 1.05, 1.0};
  {
    const FitProblem p = problem_of(framed(0.02, 0.007), 3);
    const Fit ref = fit_model(runs, p, {}, base, Samples::training, kMaxEvalBase);
    GiveUp g = screen_for(p, ref, pwm);
    const int r0 = runs.count();
    const Fit screened = fit_with_effect(runs, p, ref, pwm, &g);
    const int r1 = runs.count();
    const Fit plain = fit_with_effect(runs, p, ref, pwm);
    std::printf("20 ms frames: clock %.4f ms at %.3f ms, loss %.4g -> %.4g; %d model runs screened, %d without\n",
                screened.x[kNumBase], screened.x[kNumBase + 1], ref.train, screened.train, r1 - r0,
                runs.count() - r1);
    EXPECT_FALSE(g.stopped);
    EXPECT_EQ(screened.x, plain.x);
    EXPECT_EQ(r1 - r0, runs.count() - r1);
    EXPECT_NEAR(screened.x[kNumBase], 20.0, 0.05);
  }
  {
    const int coulomb = effect_variants("coulomb_friction").at(0);
    std::vector<double> x = base;
    x.push_back(0.007);
    const FitProblem p = problem_of(model_config(test_datasheet(), {coulomb}, x), 1);
    const Fit ref = fit_model(runs, p, {coulomb}, x, Samples::training, kMaxEvalBase);
    GiveUp g = screen_for(p, ref, pwm);
    const int r0 = runs.count();
    const Fit screened = fit_with_effect(runs, p, ref, pwm, &g);
    const int r1 = runs.count();
    const Fit plain = fit_with_effect(runs, p, ref, pwm);
    std::printf("no frames: %s, %d model runs screened (%d each clock's fit), %d without; loss %.4g, screened "
                "%.4g, without %.4g\n",
                g.stopped ? "stopped" : "not stopped", r1 - r0, g.after, runs.count() - r1, ref.train,
                screened.train, plain.train);
    ASSERT_TRUE(plain.valid) << "no clock found: the case does not test the screen";
    EXPECT_GT(plain.train, ref.train);
    EXPECT_TRUE(g.stopped);
    EXPECT_GT(screened.train, g.loss);
    EXPECT_EQ(screened.evals, g.after);   // its one clock's fit, stopped there
    EXPECT_LT(r1 - r0, runs.count() - r1);
  }
}

}  // namespace
}  // namespace chainsim
