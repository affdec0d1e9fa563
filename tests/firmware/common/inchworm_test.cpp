// The inchworm schedule (firmware/common/inchworm.c): reading SET_GAIT's
// fields, and the phase sequence every support and extension follows from
// the shared gait clock.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

extern "C" {
#include "chain_commands.h"
#include "inchworm.h"
}

namespace {

std::vector<uint8_t> gait8_frame(int16_t step_ms, int16_t index, uint8_t n_sup)
{
    std::vector<uint8_t> f(CC_SET_GAIT_LEN, 0);
    f[0] = CC_SET_GAIT;
    f[CC_GAIT_OFF_GAIT] = GAIT_INCHWORM;
    cc_put_i16(f.data() + CC_GAIT_OFF_STEP, step_ms);
    cc_put_i16(f.data() + CC_GAIT_OFF_INDEX, index);
    f[CC_GAIT_OFF_NSUP] = n_sup;
    return f;
}

iw_schedule read(const std::vector<uint8_t> &f)
{
    iw_schedule s{0xFFFF, 0xFF, 0xFF, 0xFF};
    iw_read_schedule(f.data(), &s);
    return s;
}

} // namespace

TEST(Inchworm, ReadScheduleTakesTheFramesFields)
{
    iw_schedule s = read(gait8_frame(500, 2, 3));
    EXPECT_EQ(s.step_ms, 500);
    EXPECT_EQ(s.index, 2);
    EXPECT_EQ(s.n_sup, 3);
    s = read(gait8_frame(30000, 255, 255));
    EXPECT_EQ(s.step_ms, 30000);
    EXPECT_EQ(s.index, 255);
    EXPECT_EQ(s.n_sup, 255);
}

TEST(Inchworm, ReadScheduleClampsWhatTheScheduleCannotUse)
{
    EXPECT_EQ(read(gait8_frame(39, 0, 2)).step_ms, 40) << "a step is at least 40 ms";
    EXPECT_EQ(read(gait8_frame(-500, 0, 2)).step_ms, 40);
    EXPECT_EQ(read(gait8_frame(40, 0, 2)).step_ms, 40);
    EXPECT_EQ(read(gait8_frame(1000, -3, 2)).index, 0);
    EXPECT_EQ(read(gait8_frame(1000, 256, 2)).index, 255);
    EXPECT_EQ(read(gait8_frame(1000, 0, 0)).n_sup, 1) << "no supports counts as one";
}

// S E S, 1 s steps: step 0 (0..999 ms) moves the head support, step 1 the tail
TEST(Inchworm, SupportReleasesForThreeQuartersOfItsOwnStep)
{
    const uint16_t step = 1000;
    const uint8_t n = 2;
    for (uint32_t t : {0u, 1u, 500u, 749u})
        EXPECT_FALSE(iw_support_grips(t, step, n, 0)) << "support 0 at " << t;
    for (uint32_t t : {750u, 999u, 1000u, 1500u, 1999u})
        EXPECT_TRUE(iw_support_grips(t, step, n, 0)) << "support 0 at " << t;
    for (uint32_t t : {0u, 749u, 999u, 1750u, 1999u})
        EXPECT_TRUE(iw_support_grips(t, step, n, 1)) << "support 1 at " << t;
    for (uint32_t t : {1000u, 1749u})
        EXPECT_FALSE(iw_support_grips(t, step, n, 1)) << "support 1 at " << t;
    // the cycle repeats
    EXPECT_FALSE(iw_support_grips(2000, step, n, 0));
    EXPECT_FALSE(iw_support_grips(2000u + 7u * 2000u + 1100u, step, n, 1));
}

TEST(Inchworm, ExtensionExtendsInItsStepAndRetractsInTheNext)
{
    const uint16_t step = 1000;
    const uint8_t n = 2; // one extension, 0, between support 0 and 1
    const struct {
        uint32_t t;
        bool extended;
    } want[] = {
        {0, false},    {249, false},  {250, true},   {999, true}, // step 0: pushes support 0
        {1000, true},  {1249, true},  {1250, false}, {1999, false}, // step 1: pulls support 1
        {2000, false}, {2250, true},
    };
    for (const auto &w : want)
        EXPECT_EQ(iw_extension_extended(w.t, step, n, 0) != 0, w.extended) << "t = " << w.t;
}

// What makes it an inchworm, for chains of 1 to 6 supports: at most one
// support is released at a time, every support releases once per cycle, and
// an extension changes length only while a support next to it is released
// (never while both of its supports grip the pipe).
TEST(Inchworm, OneSupportMovesAtATimeAndExtensionsMoveOnlyAFreeSupport)
{
    const uint16_t step = 40;
    for (uint8_t n = 1; n <= 6; n++) {
        const uint32_t cycle = uint32_t(n) * step;
        std::vector<uint32_t> released_ms(n, 0);
        for (uint32_t t = 0; t < 2 * cycle; t++) {
            int released = 0;
            for (uint8_t i = 0; i < n; i++)
                if (!iw_support_grips(t, step, n, i)) {
                    released++;
                    released_ms[i]++;
                }
            ASSERT_LE(released, 1) << "n = " << int(n) << ", t = " << t;
            for (uint8_t j = 0; j + 1 < n; j++) {
                bool now = iw_extension_extended(t, step, n, j);
                bool next = iw_extension_extended(t + 1, step, n, j);
                if (now == next)
                    continue;
                bool free = !iw_support_grips(t, step, n, j) || !iw_support_grips(t, step, n, j + 1);
                bool free_next = !iw_support_grips(t + 1, step, n, j) ||
                                 !iw_support_grips(t + 1, step, n, j + 1);
                EXPECT_TRUE(free && free_next)
                    << "extension " << int(j) << " of n = " << int(n) << " moves at " << t
                    << " while both its supports grip";
            }
        }
        for (uint8_t i = 0; i < n; i++)
            EXPECT_EQ(released_ms[i], 2u * (3u * step / 4u)) << "support " << int(i) << " of " << int(n);
    }
}

TEST(Inchworm, ExtensionsOfAChainExtendAndRetractOncePerCycle)
{
    const uint16_t step = 100;
    const uint8_t n = 4;
    for (uint8_t j = 0; j + 1 < n; j++) {
        int extends = 0, retracts = 0;
        for (uint32_t t = 0; t < uint32_t(n) * step; t++) {
            bool a = iw_extension_extended(t, step, n, j);
            bool b = iw_extension_extended(t + 1, step, n, j);
            extends += !a && b;
            retracts += a && !b;
        }
        EXPECT_EQ(extends, 1) << "extension " << int(j);
        EXPECT_EQ(retracts, 1) << "extension " << int(j);
        // it extends a quarter into step j and retracts a quarter into step j + 1
        EXPECT_FALSE(iw_extension_extended(j * step + step / 4 - 1, step, n, j));
        EXPECT_TRUE(iw_extension_extended(j * step + step / 4, step, n, j));
        EXPECT_TRUE(iw_extension_extended((j + 1) * step + step / 4 - 1, step, n, j));
        EXPECT_FALSE(iw_extension_extended((j + 1) * step + step / 4, step, n, j));
    }
}

// a zero step or supports count (never from iw_read_schedule) must not divide by zero
TEST(Inchworm, ZeroStepOrCountDoesNotDivideByZero)
{
    EXPECT_FALSE(iw_support_grips(12345, 0, 0, 0));
    EXPECT_TRUE(iw_support_grips(12345, 0, 0, 1));
    EXPECT_FALSE(iw_extension_extended(12345, 0, 0, 0));
}

// the clock is ms since START and may run for weeks: the schedule stays periodic
TEST(Inchworm, LateInTheClockTheScheduleIsTheSame)
{
    const uint16_t step = 500;
    const uint8_t n = 3;
    const uint32_t cycle = 1500;
    const uint32_t late = cycle * 2000000u; // about 35 days
    for (uint32_t t = 0; t < cycle; t += 7)
        for (uint8_t i = 0; i < n; i++) {
            ASSERT_EQ(iw_support_grips(late + t, step, n, i), iw_support_grips(t, step, n, i));
            ASSERT_EQ(iw_extension_extended(late + t, step, n, i),
                      iw_extension_extended(t, step, n, i));
        }
}

// ---- gait 13: every extension at once (paper 6.5) ----

namespace {

std::vector<uint8_t> gait13_frame(int16_t step_ms, int16_t index, uint8_t n_sup)
{
    std::vector<uint8_t> f = gait8_frame(step_ms, index, n_sup);
    f[CC_GAIT_OFF_GAIT] = GAIT_INCHWORM_ALL;
    return f;
}

} // namespace

TEST(InchwormAll, ReadScheduleKeepsTheGait)
{
    EXPECT_EQ(read(gait13_frame(500, 1, 4)).gait, GAIT_INCHWORM_ALL);
    EXPECT_EQ(read(gait8_frame(500, 1, 4)).gait, GAIT_INCHWORM);
    std::vector<uint8_t> f = gait8_frame(500, 1, 4);
    f[CC_GAIT_OFF_GAIT] = GAIT_HOLD;
    EXPECT_EQ(read(f).gait, GAIT_INCHWORM) << "any other code runs gait 8's schedule";
}

// S E S E S E S, 1 s steps: step 0 the tail holds and every extension
// pushes, step 1 the head holds and every extension pulls
TEST(InchwormAll, TheTailHoldsThePushAndTheHeadThePull)
{
    const uint16_t step = 1000;
    const uint8_t n = 4;
    const struct {
        uint32_t t;
        bool grips[4];
        bool extended;
    } want[] = {
        {0, {false, false, false, true}, false},   // push: the others released, extensions still in
        {249, {false, false, false, true}, false},
        {250, {false, false, false, true}, true},  // every extension out
        {749, {false, false, false, true}, true},
        {750, {true, false, false, true}, true},   // the head grips: the handover
        {999, {true, false, false, true}, true},
        {1000, {true, false, false, false}, true}, // pull: the tail and the middle released
        {1250, {true, false, false, false}, false}, // every extension in
        {1750, {true, false, false, true}, false},  // the tail grips: the handover
        {2000, {false, false, false, true}, false}, // the next cycle
    };
    for (const auto &w : want) {
        for (uint8_t i = 0; i < n; i++)
            EXPECT_EQ(iw_all_support_grips(w.t, step, n, i) != 0, w.grips[i]) << "support " << int(i) << " at " << w.t;
        EXPECT_EQ(iw_all_extended(w.t, step) != 0, w.extended) << "t = " << w.t;
    }
}

// With S E S (and a lone support) gait 13 is gait 8 tick for tick
TEST(InchwormAll, WithTwoSupportsItIsGaitEight)
{
    const uint16_t step = 100;
    for (uint32_t t = 0; t < 4u * step; t++) {
        for (uint8_t i = 0; i < 2; i++)
            ASSERT_EQ(iw_all_support_grips(t, step, 2, i), iw_support_grips(t, step, 2, i)) << t;
        ASSERT_EQ(iw_all_extended(t, step), iw_extension_extended(t, step, 2, 0)) << t;
        ASSERT_TRUE(iw_all_support_grips(t, step, 1, 0)) << "a lone support holds";
    }
}

// What makes it the paper's gait, for chains of 2 to 8 supports: the
// extensions change length only while exactly one end support grips and
// all the others are released (so the whole stroke of every extension goes
// into moving the chain, n - 1 strokes a step), the gripping end is the
// tail while they extend and the head while they retract, and at least one
// support grips at every instant
TEST(InchwormAll, EveryExtensionMovesTheChainAgainstOneEndSupport)
{
    const uint16_t step = 40;
    for (uint8_t n = 2; n <= 8; n++) {
        int extends = 0, retracts = 0;
        for (uint32_t t = 0; t < 4u * step; t++) {
            int gripping = 0;
            for (uint8_t i = 0; i < n; i++)
                gripping += iw_all_support_grips(t, step, n, i);
            ASSERT_GE(gripping, 1) << "n = " << int(n) << ", t = " << t;
            const bool now = iw_all_extended(t, step), next = iw_all_extended(t + 1, step);
            if (now == next)
                continue;
            extends += next;
            retracts += now;
            for (uint32_t u : {t, t + 1}) {
                const uint8_t anchor = next ? n - 1 : 0;
                for (uint8_t i = 0; i < n; i++)
                    EXPECT_EQ(iw_all_support_grips(u, step, n, i) != 0, i == anchor)
                        << "n = " << int(n) << ", support " << int(i) << " at " << u;
            }
        }
        EXPECT_EQ(extends, 2) << "n = " << int(n);
        EXPECT_EQ(retracts, 2) << "n = " << int(n);
    }
}

// the schedule dispatches on the frame's gait
TEST(InchwormAll, TheScheduleRunsItsGait)
{
    const iw_schedule s8 = read(gait8_frame(100, 1, 4)), s13 = read(gait13_frame(100, 1, 4));
    for (uint32_t t = 0; t < 800; t += 5) {
        ASSERT_EQ(iw_grips(&s8, t), iw_support_grips(t, 100, 4, 1));
        ASSERT_EQ(iw_extended(&s8, t), iw_extension_extended(t, 100, 4, 1));
        ASSERT_EQ(iw_grips(&s13, t), iw_all_support_grips(t, 100, 4, 1));
        ASSERT_EQ(iw_extended(&s13, t), iw_all_extended(t, 100));
    }
}
