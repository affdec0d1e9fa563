/* Fixed-point sine: see fixed_sin.h. Integer-only (SDCC pic16 friendly). */
#include "fixed_sin.h"

/* round(32767 * sin(i * pi / 128)), i = 0..64: the first quarter turn in 64 steps */
static const int16_t fs_quarter[65] = {
        0,   804,  1608,  2410,  3212,  4011,  4808,  5602,
     6393,  7179,  7962,  8739,  9512, 10278, 11039, 11793,
    12539, 13279, 14010, 14732, 15446, 16151, 16846, 17530,
    18204, 18868, 19519, 20159, 20787, 21403, 22005, 22594,
    23170, 23731, 24279, 24811, 25329, 25832, 26319, 26790,
    27245, 27683, 28105, 28510, 28898, 29268, 29621, 29956,
    30273, 30571, 30852, 31113, 31356, 31580, 31785, 31971,
    32137, 32285, 32412, 32521, 32609, 32678, 32728, 32757,
    32767
};

/* sin over the first quarter, x = 0..0x4000 (0x4000 = pi/2) */
static int16_t fs_quarter_sin(uint16_t x)
{
    uint8_t seg;
    uint8_t frac;
    int32_t lo, step;

    if (x >= 0x4000u)
        return FS_ONE_Q15;
    seg = (uint8_t)(x >> 8);   /* 0..63 */
    frac = (uint8_t)(x & 0xFFu);
    lo = fs_quarter[seg];
    step = (int32_t)fs_quarter[seg + 1u] - lo; /* > 0: the table rises */
    return (int16_t)(lo + (step * (int32_t)frac + 128L) / 256L);
}

int16_t fs_sin_bam(uint16_t angle)
{
    uint16_t x = (uint16_t)(angle & 0x3FFFu);
    uint8_t quadrant = (uint8_t)(angle >> 14);
    int16_t v;

    if (quadrant & 1u)
        x = (uint16_t)(0x4000u - x); /* falling half of the hump: mirror */
    v = fs_quarter_sin(x);
    return (quadrant & 2u) ? (int16_t)-v : v;
}

int16_t fs_wrap_mrad(int32_t angle_mrad)
{
    int32_t r = angle_mrad % FS_TWO_PI_MRAD;
    if (r < 0)
        r += FS_TWO_PI_MRAD;
    return (int16_t)r;
}

/* 0..6282 mrad to BAM16, rounded: r * 65536 / 6283 (r * 65536 < 2^32);
 * 6283 itself would be 65536, which wraps to the same angle 0 */
static uint16_t fs_mrad_to_bam(int32_t angle_mrad)
{
    uint32_t r = (uint32_t)fs_wrap_mrad(angle_mrad);
    return (uint16_t)((uint32_t)(r * 65536UL + (uint32_t)(FS_TWO_PI_MRAD / 2)) /
                      (uint32_t)FS_TWO_PI_MRAD);
}

int16_t fs_sin_mrad(int32_t angle_mrad)
{
    return fs_sin_bam(fs_mrad_to_bam(angle_mrad));
}

int16_t fs_cos_mrad(int32_t angle_mrad)
{
    /* cos x = sin(x + quarter turn) */
    return fs_sin_bam((uint16_t)(fs_mrad_to_bam(angle_mrad) + 0x4000u));
}

int16_t fs_scale(int16_t amplitude, int16_t q15)
{
    int32_t p = (int32_t)amplitude * (int32_t)q15;
    if (p >= 0)
        return (int16_t)((p + 16384L) / 32768L);
    return (int16_t)-((-p + 16384L) / 32768L);
}
