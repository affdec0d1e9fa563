// The firmware's fixed-point sine and gait arithmetic against <cmath>.
#include <cmath>
#include <cstdint>
#include <cstdio>

#include <gtest/gtest.h>

extern "C" {
#include "fixed_sin.h"
#include "gait.h"
}

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kQ15 = 32767.0; // fs output for 1.0

// stated accuracy (also in fixed_sin.h)
constexpr double kMaxErrBam = 1.0e-4;  // table + interpolation + rounding (~3.2 Q15 counts)
constexpr double kMaxErrMrad = 3.0e-4; // + whole-mrad input and the 6283-mrad period

} // namespace

TEST(FixedSin, BamOverEveryAngle)
{
    double max_err = 0;
    for (uint32_t a = 0; a < 65536; a++) {
        double want = std::sin(2.0 * kPi * a / 65536.0);
        double err = std::fabs(fs_sin_bam(uint16_t(a)) / kQ15 - want);
        max_err = std::max(max_err, err);
    }
    std::printf("[          ] fs_sin_bam max |error| = %.2e (%.2f Q15 counts)\n", max_err,
                max_err * 32768);
    EXPECT_LE(max_err, kMaxErrBam);
}

TEST(FixedSin, BamExactPointsAndSymmetry)
{
    EXPECT_EQ(fs_sin_bam(0), 0);
    EXPECT_EQ(fs_sin_bam(0x4000), 32767);
    EXPECT_EQ(fs_sin_bam(0x8000), 0);
    EXPECT_EQ(fs_sin_bam(0xC000), -32767);
    for (uint32_t a = 1; a < 65536; a++) {
        ASSERT_EQ(fs_sin_bam(uint16_t(65536 - a)), -fs_sin_bam(uint16_t(a))) << a; // odd
        ASSERT_EQ(fs_sin_bam(uint16_t(0x8000 - a)), fs_sin_bam(uint16_t(a))) << a; // sin(pi-x)
    }
}

TEST(FixedSin, MradOverSeveralTurnsBothSigns)
{
    double max_err = 0;
    for (int32_t x = -40000; x <= 40000; x++) {
        double want = std::sin(x / 1000.0);
        // compare at the angle reduced with the true 2*pi so that only the
        // function's error (table + its 6283 period) is measured, not drift
        double r = std::fmod(x, 6283.0);
        if (r < 0)
            r += 6283.0;
        want = std::sin(r / 1000.0);
        double err = std::fabs(fs_sin_mrad(x) / kQ15 - want);
        max_err = std::max(max_err, err);
        double errc = std::fabs(fs_cos_mrad(x) / kQ15 - std::cos(r / 1000.0));
        max_err = std::max(max_err, errc);
    }
    std::printf("[          ] fs_sin_mrad/fs_cos_mrad max |error| = %.2e (%.2f Q15 counts)\n",
                max_err, max_err * 32768);
    EXPECT_LE(max_err, kMaxErrMrad);
    EXPECT_EQ(fs_sin_mrad(INT32_MAX), fs_sin_mrad(INT32_MAX % 6283));
    EXPECT_EQ(fs_sin_mrad(INT32_MIN), fs_sin_mrad(INT32_MIN % 6283 + 6283));
}

TEST(FixedSin, WrapAndScale)
{
    EXPECT_EQ(fs_wrap_mrad(0), 0);
    EXPECT_EQ(fs_wrap_mrad(6283), 0);
    EXPECT_EQ(fs_wrap_mrad(-1), 6282);
    EXPECT_EQ(fs_wrap_mrad(-6284), 6282);
    EXPECT_EQ(fs_wrap_mrad(12567), 1);
    EXPECT_EQ(fs_scale(4000, 32767), 4000);
    EXPECT_EQ(fs_scale(4000, -32767), -4000);
    EXPECT_EQ(fs_scale(18000, 16384), 9000);
    EXPECT_EQ(fs_scale(-100, 16384), -50);
    EXPECT_EQ(fs_scale(3, 16384), 2);   // 1.5 -> 2
    EXPECT_EQ(fs_scale(3, -16384), -2); // halves away from zero
    EXPECT_EQ(fs_scale(0, 12345), 0);
}

TEST(Gait, PhaseMatchesExactArithmeticForAnyTime)
{
    const int16_t omegas[] = {0, 1, 6000, -6000, 32767, -32767, 6283, 12566};
    const uint32_t times[] = {0u, 1u, 999u, 1000u, 123456u, 3600000u, 86400000u,
                              2147483647u, 4294967295u};
    const int32_t offsets[] = {0, 1000, -7000, 2000000};
    for (int16_t w : omegas)
        for (uint32_t t : times)
            for (int32_t off : offsets) {
                // exact: floor(w*t/1000) (trunc for w<0 on the sub-second part) + off, mod 6283
                int64_t q = t / 1000, r = t % 1000;
                int64_t exact = int64_t(w) * q + (int64_t(w) * r) / 1000 + off;
                int64_t want = ((exact % 6283) + 6283) % 6283;
                ASSERT_EQ(gait_phase_mrad(w, t, off), want) << w << " " << t << " " << off;
            }
}

TEST(Gait, AngleIsAmplitudeTimesSine)
{
    // the documented definition: one turn = 6283 mrad, i.e. the wave runs
    // 6283.185/6283 = 1.00003 times faster than omega (same for every module,
    // so the phase relations between modules are exact)
    const double turn = 2.0 * kPi / 6283.0;
    double max_err = 0, max_drift = 0;
    for (uint32_t t = 0; t < 20000; t += 7) {
        for (int k = 0; k < 8; k++) {
            double phase = 6000.0 * t / 1000.0 + k * 1000.0; // mrad
            double want = 4000.0 * std::sin(turn * phase);
            double got = gait_angle_cdeg(4000, 6000, t, k * 1000);
            max_err = std::max(max_err, std::fabs(got - want));
            max_drift = std::max(max_drift, std::fabs(got - 4000.0 * std::sin(phase / 1000.0)));
        }
    }
    std::printf("[          ] gait_angle_cdeg max |error| = %.2f cdeg (vs exact 2*pi: %.2f cdeg "
                "after 20 s)\n",
                max_err, max_drift);
    EXPECT_LE(max_err, 6.0); // whole-mrad phase (<= 4 cdeg) + sine table + rounding
}
