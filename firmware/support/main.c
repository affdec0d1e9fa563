/* Support module firmware (paper 3.3.3): servo 0 opens the three arms
 * (0 = closed, 9000 cdeg = perpendicular); opened against the pipe wall they
 * anchor the module.
 *
 * Gait 8 (inchworm) and gait 13 (inchworm, every extension at once):
 * SET_GAIT gives the grip angle, the step duration, this support's index i
 * and the number of supports n (chain_commands.h); from START, every
 * control_ms it opens the arms to the grip angle or closes them (0) as the
 * gait's schedule in inchworm.h says for support i. STOP: it grips
 * and holds (so that a chain in a vertical pipe does not fall); SET_GAIT
 * with gait 0: arms closed. Gait 11 (hold; the elbow of paper 6.6): SET_GAIT
 * opens the arms to its grip angle at once, without START, and holds them
 * until SET_GAIT with gait 0 or STOP (which keeps the grip). Any other gait
 * sets CC_FLAG_BAD_GAIT.
 * READ_SENSORS: SENSORS with 2 values, the measured arm angle (cdeg) and
 * the arm servo's current in ADC counts (ADC 0). See docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"
#include "inchworm.h"

#define SERVO_ARM 0u

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM_END
};

static int16_t grip_cdeg = CC_QUARTER_TURN_CDEG;
static iw_schedule sched = {1000, 0, 1, GAIT_INCHWORM};

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to;
    int16_t v[2];
    int16_t g;
    uint8_t periodic;

    hal_init();
    chain_app_servo(SERVO_ARM, 0);
    chain_app_init(MT_SUPPORT);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                g = buf[CC_GAIT_OFF_GAIT];
                (void)chain_app_take_gait(buf, g == GAIT_HOLD || g == GAIT_INCHWORM_ALL ? (uint8_t)g : GAIT_INCHWORM);
                g = cc_get_i16(buf + CC_GAIT_OFF_GRIP);
                grip_cdeg = g < 0 ? 0 : (g > CC_QUARTER_TURN_CDEG ? CC_QUARTER_TURN_CDEG : g);
                if (ca_gait == GAIT_HOLD) {
                    /* grip at once and hold (no schedule, no control step) */
                    ca_running = 1;
                    chain_app_servo(SERVO_ARM, grip_cdeg);
                    break;
                }
                iw_read_schedule(buf, &sched);
                if (ca_gait == GAIT_NONE) {
                    ca_running = 0;
                    chain_app_servo(SERVO_ARM, 0);
                }
                break;
            case CC_START:
                ca_running = ca_gait == GAIT_INCHWORM || ca_gait == GAIT_INCHWORM_ALL;
                if (ca_gait != GAIT_NONE && !ca_running)
                    hal_log("start: gait not supported by support module");
                chain_app_clock_start();
                break;
            case CC_STOP:
                if (ca_running)
                    chain_app_servo(SERVO_ARM, grip_cdeg);
                ca_running = 0;
                break;
            case CC_READ_SENSORS:
                v[0] = hal_servo_angle_cdeg(SERVO_ARM);
                v[1] = (int16_t)hal_adc_read(0);
                chain_app_sensors(v, 2);
                break;
            default:
                break;
            }
        }
        periodic = ca_running && ca_gait != GAIT_HOLD;
        if (chain_app_wait(periodic) && periodic)
            chain_app_servo(SERVO_ARM, iw_grips(&sched, chain_app_clock_ms()) ? grip_cdeg : 0);
    }
}
