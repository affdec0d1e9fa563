/* Where a touch module was touched: see touch_direction.h. */
#include "touch_direction.h"

#include "fixed_sin.h"

int16_t td_atan2_deg(int16_t y, int16_t x)
{
    int32_t ax = x < 0 ? -(int32_t)x : x, ay = y < 0 ? -(int32_t)y : y;
    int32_t mn, mx, t, a;
    if (ax == 0 && ay == 0)
        return TD_NONE;
    mn = ax < ay ? ax : ay;
    mx = ax < ay ? ay : ax;
    t = (mn << 10) / mx; /* tan of the angle to the nearer axis, Q10: 0..1024 */
    /* atan(t) = 45 t + 15.64 t (1 - t) degrees on 0..1 (within 0.22
     * degree), here in hundredths of a degree */
    a = (4500L * t) >> 10;
    a += (1564L * t * (1024L - t)) >> 20;
    if (ay > ax)
        a = 9000 - a;
    if (x < 0)
        a = 18000 - a;
    if (y < 0)
        a = 36000 - a;
    a = (a + 50) / 100;
    return (int16_t)(a >= 360 ? a - 360 : a);
}

int16_t td_direction(uint8_t closed, uint8_t n, int16_t first_deg)
{
    int32_t up = 0, left = 0;
    uint8_t k;
    if (n == 0)
        return TD_NONE;
    for (k = 0; k < n; k++) {
        if (closed & (uint8_t)(1u << k)) {
            int32_t deg = (int32_t)first_deg + (int32_t)k * 360 / n;
            int32_t mrad = deg * 17453L / 1000L;
            up += fs_cos_mrad(mrad);
            left += fs_sin_mrad(mrad);
        }
    }
    /* balanced: the sum is within the table's rounding of zero */
    if (up < 64 && up > -64 && left < 64 && left > -64)
        return TD_NONE;
    return td_atan2_deg((int16_t)(left / 4), (int16_t)(up / 4));
}

int16_t td_up_deg(int16_t y_counts, int16_t z_counts, int16_t zero_counts)
{
    int16_t y = (int16_t)(y_counts - zero_counts), z = (int16_t)(z_counts - zero_counts);
    /* gravity within about 17 degrees of the axis: no roll to speak of (a
     * 10-bit reading of 1 g is about 170 counts) */
    if (y < 50 && y > -50 && z < 50 && z > -50)
        return TD_NONE;
    return td_atan2_deg(y, z);
}

int16_t td_world_deg(int16_t dir_deg, int16_t up_deg)
{
    int16_t d;
    if (dir_deg == TD_NONE || up_deg == TD_NONE)
        return TD_NONE;
    d = (int16_t)(dir_deg - up_deg);
    while (d < 0)
        d += 360;
    while (d >= 360)
        d -= 360;
    return d;
}

uint8_t td_side(int16_t world_deg)
{
    if (world_deg == TD_NONE)
        return CC_SIDE_NONE;
    if (world_deg < 45 || world_deg >= 315)
        return CC_SIDE_UP;
    if (world_deg < 135)
        return CC_SIDE_LEFT;
    if (world_deg < 225)
        return CC_SIDE_DOWN;
    return CC_SIDE_RIGHT;
}
