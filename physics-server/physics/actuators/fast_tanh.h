// tanh without the library call, for the servo model's Coulomb friction
// (servo_model_step.h), which takes one per step: glibc's tanh (through its
// expm1) waits about 45 ns per call on the calibration's critical path, this
// one 0.6 of that, and inlined, two models stepped side by side overlap it
// (servo_stand_bench, docs/benchmarks.md).
//
//   tanh(x) = sign(x) m / (m + 2),  m = e^(2|x|) - 1,  +-1 for |x| >= 20;
//   e^y = 2^k e^r,  k = round(y / ln 2),  r = y - k ln 2 (ln 2 in two parts,
//   so that k ln2_hi is exact);  e^r - 1 by its Taylor series to r^13
//   (|r| <= ln 2 / 2: the first term left out is below 6e-18 of e^r), as
//   r + r^2 P(r) with P by Estrin's scheme (a shorter chain of dependent
//   operations than Horner's);  m = 2^k (e^r - 1) + (2^k - 1), which for
//   k = 0 (|x| < 0.174) is the series itself, with no cancellation, so small
//   arguments keep their relative accuracy.
//
// Accuracy: within 3 ulp of the exact tanh (the unit test measures 20
// million arguments against long double's tanhl; glibc's tanh: 2.2 ulp);
// not monotone to the last ulp (it can step back 1-2 ulp from one double to
// the next, which the friction's smoothing does not mind). Exact 0 at 0 with
// its sign, +-1 from about 19.06 on (as the exact tanh rounds), NaN for NaN.
// Only additions, multiplications, one division and exact bit operations,
// none contracted into an FMA (the project's build targets baseline x86-64):
// the same bits on every x86-64 CPU and with every C library.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace chainsim {

[[gnu::always_inline]] inline double fast_tanh(double x) {
  const double a = std::fabs(x);
  if (!(a < 20.0)) return a == a ? std::copysign(1.0, x) : x;
  constexpr double kInvLn2 = 1.4426950408889634;
  // ln 2 = kLn2Hi + kLn2Lo, kLn2Hi with its low 21 bits zero
  constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;
  const double y = 2.0 * a;
  // k = round(y / ln 2) by the 1.5 * 2^52 shift: k ends in the low bits of z
  constexpr double kShift = 0x1.8p52;
  const double z = y * kInvLn2 + kShift;
  const double kd = z - kShift;
  const uint64_t zb = std::bit_cast<uint64_t>(z);
  const double r = (y - kd * kLn2Hi) - kd * kLn2Lo;
  constexpr double c2 = 1.0 / 2, c3 = 1.0 / 6, c4 = 1.0 / 24, c5 = 1.0 / 120, c6 = 1.0 / 720, c7 = 1.0 / 5040,
                   c8 = 1.0 / 40320, c9 = 1.0 / 362880, c10 = 1.0 / 3628800, c11 = 1.0 / 39916800,
                   c12 = 1.0 / 479001600, c13 = 1.0 / 6227020800;
  // e^r - 1 = r + r^2 P(r), P = c2 + c3 r + ... + c13 r^11 by Estrin's
  // scheme; r added last, so the sum rounds once at r's scale
  const double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  const double p23 = c2 + c3 * r, p45 = c4 + c5 * r, p67 = c6 + c7 * r, p89 = c8 + c9 * r, pab = c10 + c11 * r,
               pcd = c12 + c13 * r;
  const double q0 = p23 + p45 * r2, q1 = p67 + p89 * r2, q2 = pab + pcd * r2;
  const double big_p = (q0 + q1 * r4) + q2 * r8;
  const double em_r = r + r2 * big_p;   // e^r - 1
  // 2^k from k's bits (0 <= k <= 58)
  const double scale = std::bit_cast<double>((zb + 1023) << 52);
  // m = 2^k (e^r - 1) + (2^k - 1): both parts exact (k <= 53; beyond,
  // tanh is 1 within 1 ulp), one rounding; for k = 0 the series itself
  const double m = em_r * scale + (scale - 1.0);
  return std::copysign(m / (m + 2.0), x);
}

}  // namespace chainsim
