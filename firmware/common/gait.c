/* Travelling-wave gait arithmetic: see gait.h. */
#include "gait.h"

#include "fixed_sin.h"

int16_t gait_phase_mrad(int16_t omega_mrad_s, uint32_t t_ms, int32_t offset_mrad)
{
    /* omega*t/1000 = omega*q + omega*r/1000 with t = 1000*q + r; omega*q is
     * reduced as (omega mod 2pi) * (q mod 2pi), each factor < 6283, so every
     * product stays below 2^31 whatever t is (t wraps after ~49 days). */
    uint32_t q = t_ms / 1000UL;
    int32_t r = (int32_t)(t_ms % 1000UL);
    int32_t w = fs_wrap_mrad(omega_mrad_s);               /* 0..6282 */
    int32_t qm = (int32_t)(q % (uint32_t)FS_TWO_PI_MRAD); /* 0..6282 */
    int32_t a = (w * qm) % FS_TWO_PI_MRAD;                /* < 6283^2 < 2^31 */
    int32_t b = ((int32_t)omega_mrad_s * r) / 1000L;      /* |b| < 32768 */
    int32_t c = fs_wrap_mrad(offset_mrad);
    return fs_wrap_mrad(a + b + c);
}

int16_t gait_angle_cdeg(int16_t amp_cdeg, int16_t omega_mrad_s, uint32_t t_ms,
                        int32_t offset_mrad)
{
    return fs_scale(amp_cdeg, fs_sin_mrad(gait_phase_mrad(omega_mrad_s, t_ms, offset_mrad)));
}
