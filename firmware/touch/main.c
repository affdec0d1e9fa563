/* Touch module firmware (paper 3.3.5): a cover resting on three contact
 * switches 120 degrees apart around the module's axis, on digital inputs 0,
 * 1, 2 (switch 0 on top, then 120 and 240 degrees: towards the left and
 * round; scenes/modules/touch.yaml), and a 3-axis accelerometer on ADC 0,
 * 1, 2.
 *
 * From discovery on it samples the switches every control_ms. A switch is
 * closed while its input is high and until it has been low for release_ms
 * (parameter, default 50) in a row. Each change of the closed set is sent to
 * the central control as a TOUCH frame (code 0x24, addr, the closed set,
 * the obstacle's direction in the module frame and where up is, both in
 * degrees, and the obstacle's side as the world sees it: up, left, down or
 * right; touch_direction.h; a released cover sends an empty set), and any
 * closed switch sets the sticky CC_FLAG_TOUCH in STATUS_REPLY. READ_SENSORS:
 * SENSORS with 4 values, the closed set (0..7) and the accelerometer's x,
 * y, z in ADC counts (512 = 0 g, 170.7 counts per g). It has no gait:
 * SET_GAIT with a gait other than 0 sets CC_FLAG_BAD_GAIT. See
 * docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"
#include "touch_direction.h"

#define TOUCH_SWITCHES 3u    /* digital inputs 0, 1, 2 */
#define TOUCH_FIRST_DEG 0    /* switch 0 on top */
#define ACCEL_ZERO 512       /* ADC counts at 0 g */
#define ACCEL_Y 1u           /* ADC channel of the left (y) axis; z is the next */

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM("release_ms", HAL_PARAM_U16, 0, 60000, 50, "a switch is released once its input was low this long, ms"),
    HAL_PARAM_END
};

static uint32_t last_high_ms[TOUCH_SWITCHES];

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to, i;
    uint8_t closed = 0;
    uint16_t release_ms;
    int16_t v[4];

    hal_init();
    release_ms = (uint16_t)hal_param("release_ms");
    chain_app_init(MT_TOUCH);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                (void)chain_app_take_gait(buf, GAIT_NONE);
                break;
            case CC_READ_SENSORS:
                v[0] = closed;
                for (i = 0; i < 3u; i++)
                    v[i + 1u] = (int16_t)hal_adc_read(i);
                chain_app_sensors(v, 4);
                break;
            default:
                break;
            }
        }
        if (chain_app_wait(1)) {
            uint32_t now = hal_millis();
            uint8_t was = closed;
            for (i = 0; i < TOUCH_SWITCHES; i++) {
                uint8_t bit = (uint8_t)(1u << i);
                if (hal_gpio_read(i)) {
                    last_high_ms[i] = now;
                    closed |= bit;
                } else if ((closed & bit) && now - last_high_ms[i] >= release_ms) {
                    closed &= (uint8_t)~bit;
                }
            }
            if (closed)
                ca_flags |= CC_FLAG_TOUCH;
            if (closed != was) {
                int16_t dir = td_direction(closed, TOUCH_SWITCHES, TOUCH_FIRST_DEG);
                int16_t up = td_up_deg((int16_t)hal_adc_read(ACCEL_Y), (int16_t)hal_adc_read(ACCEL_Y + 1u),
                                       ACCEL_ZERO);
                buf[0] = CC_TOUCH;
                buf[1] = ca_addr;
                buf[2] = closed;
                cc_put_i16(buf + CC_TOUCH_OFF_DIR, dir);
                cc_put_i16(buf + CC_TOUCH_OFF_UP, up);
                buf[CC_TOUCH_OFF_SIDE] = td_side(td_world_deg(dir, up));
                chain_app_reply(buf, CC_TOUCH_LEN);
            }
        }
    }
}
