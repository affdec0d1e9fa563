// The pwm frame clock of a measurement: a servo that reads its set-point only
// at pulse frames (phase + n x period, the phase arbitrary on a real servo)
// answers each set-point change late by the time to the next frame. The
// delay of every change is measured against the current model (its response
// shifted in time), then the period and phase are fitted to those delays:
// a scan of the frequency, then weighted least squares of the frame times
// on their frame numbers, which gives the intervals.
// docs/calibration.md, "Method".
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "analysis/calibration/servo_fit.h"

#if defined(__x86_64__) && __has_include(<sys/platform/x86.h>)
#include <sys/platform/x86.h>
#endif

namespace chainsim {

// true where std::fma is one instruction. On x86-64 the build does not
// assume FMA (no -march), so std::fma calls glibc's fma(), which is the
// instruction where glibc finds FMA usable and an exact emulation in
// software, several times slower than fmod, where it does not (an older
// CPU, or GLIBC_TUNABLES hiding FMA). Either gives the same bits. Read once
// at start-up, not in fmod_exact's hot loop.
#if defined(__x86_64__) && __has_include(<sys/platform/x86.h>)
inline const bool kFmaIsAnInstruction = CPU_FEATURE_ACTIVE(FMA);
#else
inline const bool kFmaIsAnInstruction = true;
#endif

// std::fmod(x, p) bit for bit (p > 0), without fmod's long division where
// the quotient fits: q = trunc(x p_inv), p_inv 1 / p or near it (q may then
// be off), and r = x - q p by one fma (rounding once). The exact x - q p is
// a multiple of the smallest subnormal, so r is 0 only when it is exactly
// 0, and rounding never carries it across 0 or p (both representable): r
// lies in [0, p) (x >= 0) or (-p, 0] (x < 0) only if q is the quotient, and
// then the exact value is the remainder, which is representable, so r is
// it. Otherwise std::fmod, and always std::fmod where fma is no instruction
// (kFmaIsAnInstruction). The frame clock's scan spends most of its time
// here (fit_frame_clock)
// (the fast way alone: true with the remainder in r, false where it does
// not tell and std::fmod must)
inline bool fmod_by_fma(double x, double p, double p_inv, double& r) {
  const double qf = x * p_inv;
  if (!(std::fabs(qf) < 0x1p52)) return false;
  const double q = static_cast<double>(static_cast<int64_t>(qf));
  r = std::fma(-q, p, x);
  if (r == 0.0) {
    r = std::copysign(0.0, x);   // x a multiple of p: fmod's zero has x's sign
    return true;
  }
  return x > 0 ? (r > 0 && r < p) : (r < 0 && r > -p);
}
inline double fmod_exact(double x, double p, double p_inv) {
  double r;
  return kFmaIsAnInstruction && fmod_by_fma(x, p, p_inv, r) ? r : std::fmod(x, p);
}
inline double fmod_exact(double x, double p) { return fmod_exact(x, p, 1.0 / p); }

// v wrapped into [0, p): std::fmod(std::fmod(v, p) + p, p) bit for bit (p_inv
// as for fmod_exact). For 0 < p < 2^1022 the inner remainder r is in (-p, p),
// so r + p (rounded) is in (0, 2p], and its remainder is itself below p,
// else its difference with p (exact: p <= r + p <= 2p), which is p only at
// 2p, whose remainder is 0; any other p (zero, negative, NaN, huge) goes
// the long way, so that a bad period still gives what fmod gives
inline double wrap_to_period(double v, double p, double p_inv) {
  if (!(p > 0.0 && p < 0x1p1022)) return std::fmod(std::fmod(v, p) + p, p);
  const double s = fmod_exact(v, p, p_inv) + p;
  if (s < p) return s;
  const double t = s - p;
  return t < p ? t : 0.0;
}
inline double wrap_to_period(double v, double p) { return wrap_to_period(v, p, 1.0 / p); }

// a set-point change of more than 0.25 degrees: its first sample and time
struct SetpointChange {
  size_t k = 0;
  double t = 0;
};
std::vector<SetpointChange> setpoint_changes(const MeasuredRecord& m);

// a change's measured delay and its standard deviation (s): from the
// curvature of the misfit around the best delay, widened by the square root
// of that misfit per residual where the shifted model does not fit the change
// to the noise (an effect the model lacks, such as a deadband, then shifts
// the delay too); sd < 0: the change does not tell (its response does not
// depend on the delay)
struct ChangeDelay {
  double t = 0, delay = 0, sd = -1;
  double step_deg = 0;   // the set-point's change
  double sp_deg = 0;     // the set-point it goes to
  double shift = 0;      // s taken off the measured delay (falling_edge_delays)
};

// A second clock from the large set-point steps alone: a small step's
// response depends on effects the model may not have yet (a deadband of a
// few degrees changes a 3-5 degree step's response by half, and the delay
// that fits it best is then off by milliseconds with a narrow curvature),
// while a large step's start is the frame's; but with backlash a large
// step's start also waits for the gap to close, and the small steps help
// there. So both clocks are tried (frame_clocks_for).
constexpr double kClockMinStepDeg = 8.0;

// per change, the delay in [0, max_delay_s] at which the model b's response
// (one run on a 100 us grid, shifted) fits the measurement best in noise units
std::vector<ChangeDelay> estimate_delays(ModelRuns& runs, const FitProblem& p, const BenchConfig& b,
                                         double max_delay_s);

// frames at t0 + phase + n period (0 <= phase < period)
struct FrameClock {
  double period_s = 0, phase_s = 0;
};
// the delay the clock gives a change at t: to the first frame at or after t
double frame_delay(const FrameClock& c, double t0, double t);

struct FrameClockFit {
  bool found = false;
  FrameClock clock;
  std::pair<double, double> period_ci_s, phase_ci_s;   // 95 %
  int used = 0, inliers = 0;   // changes that tell the delay; those the clock explains
};

// the clock (period in [period_lo, period_hi]) whose delays match d: found
// when at least 4 changes, and half of those that tell, agree with it; only
// the changes of at least min_step_deg count
FrameClockFit fit_frame_clock(const std::vector<ChangeDelay>& d, double t0, double period_lo, double period_hi,
                              double min_step_deg = 0);

// whether the clocks a and b put each frame of a record of span_s within
// tol_s of each other (phases compared modulo the period): one clock, as far
// as a fit that moves the phase by tol_s can tell
bool same_frames(const FrameClock& a, const FrameClock& b, double span_s, double tol_s);

// delays against the model b, then the clock (2.5..40 ms) from every change
FrameClockFit frame_clock_for(ModelRuns& runs, const FitProblem& p, const BenchConfig& b);

// the same delays, the clocks found: from every change, and from the steps
// of kClockMinStepDeg or more alone where its frames differ from the first
// clock's by more than the fit's phase window (none, one or two)
std::vector<FrameClockFit> frame_clocks_for(ModelRuns& runs, const FitProblem& p, const BenchConfig& b);


// The delays a falling-edge decoder (docs/calibration.md, the catalogue's
// `falling_edge` form) leaves to its frames, for a pulse slope k (s/deg):
// each change waits for the next frame and then for its pulse, 1.5 ms + k
// (sp - 90 deg) wide for the set-point sp it carries, so a change's delay
// less that width is its wait for the frame. Spread by the pulse widths,
// the measured delays may make no clock at all, or a compromise
// (frame_clocks_for); corrected, they make the frames' clock. (A delay is
// never explained beyond a period, so the whole width comes off, not only
// its spread.)
std::vector<ChangeDelay> falling_edge_delays(const std::vector<ChangeDelay>& d, double k_s_per_deg);

// a clock found in the delays corrected for one pulse slope
struct PulseClock {
  double k_us_per_deg = 0;
  FrameClockFit fit;
};

// per slope (us/deg), the clocks that the delays against the model b,
// corrected so, make (from every change and from the large steps, as
// frame_clocks_for); of clocks with the same frames, the one with the most
// inliers (the first slope on a tie): one start each for the falling-edge fit
std::vector<PulseClock> pulse_clocks_for(ModelRuns& runs, const FitProblem& p, const BenchConfig& b,
                                         const std::vector<double>& slopes_us_per_deg);

}  // namespace chainsim
