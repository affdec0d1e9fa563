/* Extension module firmware (paper 3.3.4): servo 0 = the linear servo (the
 * back box slides backwards by 0..15 mm; its set-point is a length, which
 * setspangle carries as cdeg x 10 um: 1500 = 15 mm), servo 1 = the pitch
 * servo in front (held at 0).
 *
 * Gait 8 (inchworm) and gait 13 (inchworm, every extension at once):
 * SET_GAIT gives the stroke (um), the step duration, this extension's index
 * j and the number of supports n (chain_commands.h); from START, every
 * control_ms it extends to the stroke or retracts to 0 as the gait's
 * schedule in inchworm.h says for extension j. STOP: it holds its
 * length; SET_GAIT with gait 0: retracted. Any other gait sets
 * CC_FLAG_BAD_GAIT. READ_SENSORS: SENSORS with 3 values, the measured length
 * (um / 10), the pitch angle (cdeg) and the linear servo's current in ADC
 * counts (ADC 0). See docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"
#include "inchworm.h"

#define SERVO_SLIDE 0u
#define SERVO_PITCH 1u
#define STROKE_MAX_UM 15000

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM_END
};

static int16_t stroke_um = STROKE_MAX_UM;
static iw_schedule sched = {1000, 0, 2, GAIT_INCHWORM};

static void set_length_um(int16_t um)
{
    chain_app_servo(SERVO_SLIDE, (int16_t)(um / 10));
}

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to;
    int16_t v[3];
    int16_t g;

    hal_init();
    set_length_um(0);
    chain_app_servo(SERVO_PITCH, 0);
    chain_app_init(MT_EXTENSION);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                (void)chain_app_take_gait(buf, buf[CC_GAIT_OFF_GAIT] == GAIT_INCHWORM_ALL ? GAIT_INCHWORM_ALL : GAIT_INCHWORM);
                g = cc_get_i16(buf + CC_GAIT_OFF_STROKE);
                stroke_um = g < 0 ? 0 : (g > STROKE_MAX_UM ? STROKE_MAX_UM : g);
                iw_read_schedule(buf, &sched);
                if (ca_gait == GAIT_NONE) {
                    ca_running = 0;
                    set_length_um(0);
                }
                break;
            case CC_START:
                ca_running = ca_gait == GAIT_INCHWORM || ca_gait == GAIT_INCHWORM_ALL;
                if (ca_gait != GAIT_NONE && !ca_running)
                    hal_log("start: gait not supported by extension module");
                chain_app_clock_start();
                break;
            case CC_STOP:
                ca_running = 0;
                break;
            case CC_READ_SENSORS:
                v[0] = hal_servo_angle_cdeg(SERVO_SLIDE);
                v[1] = hal_servo_angle_cdeg(SERVO_PITCH);
                v[2] = (int16_t)hal_adc_read(0);
                chain_app_sensors(v, 3);
                break;
            default:
                break;
            }
        }
        if (chain_app_wait(ca_running) && ca_running)
            set_length_um(iw_extended(&sched, chain_app_clock_ms()) ? stroke_um : 0);
    }
}
