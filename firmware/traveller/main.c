/* Traveller module firmware (paper 3.3.6): three wheels with encoders
 * (counters 0, 1, 2, in degrees of wheel rotation) at 120 degrees around
 * the module, rolling on the pipe wall.
 *
 * From discovery on, every control_ms (default 50) it reads the three counters and adds
 * the largest increment (largest in magnitude, with its sign) to the
 * distance: a wheel that loses contact with the wall under-reads, so the
 * largest is the best estimate (paper 3.3.6). The distance in mm is
 * deg x wheel_r_um / 57296 (parameter wheel_r_um, default 6000: the wheels'
 * 6 mm radius). READ_SENSORS: SENSORS with 4 values, the distance in mm
 * (+ = forward) and the three encoder totals in degrees (16 bits, they
 * wrap). It has no gait: SET_GAIT with a gait other than 0 sets
 * CC_FLAG_BAD_GAIT. See docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"

#define WHEELS 3u
#define MDEG_PER_RAD 57296 /* 360000 / (2 pi): deg x r_um / this = mm */

const hal_param_decl hal_param_table[] = {
    /* 50, not 10: at 10 ms the per-step jitter of the wheels, which the max
     * picks up, made the estimate 6 % long; 50 ms takes it to 0.3 % */
    CHAIN_APP_PARAM_CONTROL_MS(50),
    HAL_PARAM("wheel_r_um", HAL_PARAM_I32, 1, 30000, 6000, "wheel radius, um (distance = deg x wheel_r_um / 57296)"),
    HAL_PARAM_END
};

static int32_t last[WHEELS];
static int32_t dist_deg;
static int32_t wheel_r_um;

static int16_t dist_mm(void)
{
    /* |dist_deg| < 2^31 / 60000 for r = 6 mm: 37 m */
    int32_t mm = dist_deg * wheel_r_um / MDEG_PER_RAD;
    if (mm > 32767)
        return 32767;
    if (mm < -32767)
        return -32767;
    return (int16_t)mm;
}

static void sample(void)
{
    uint8_t i;
    int32_t best = 0, c, d;
    for (i = 0; i < WHEELS; i++) {
        c = hal_counter_read(i);
        d = c - last[i];
        last[i] = c;
        if ((d < 0 ? -d : d) > (best < 0 ? -best : best))
            best = d;
    }
    dist_deg += best;
}

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to, i;
    int16_t v[4];

    hal_init();
    wheel_r_um = hal_param("wheel_r_um");
    chain_app_init(MT_TRAVELLER);
    for (i = 0; i < WHEELS; i++)
        last[i] = hal_counter_read(i);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                (void)chain_app_take_gait(buf, GAIT_NONE);
                break;
            case CC_READ_SENSORS:
                sample(); /* up to date at the request */
                v[0] = dist_mm();
                for (i = 0; i < WHEELS; i++)
                    v[i + 1u] = (int16_t)last[i];
                chain_app_sensors(v, 4);
                break;
            default:
                break;
            }
        }
        if (chain_app_wait(1))
            sample();
    }
}
