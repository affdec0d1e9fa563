/* Touch module firmware (paper 3.3.5): a cover on three contact switches
 * wired to digital input 0, and a 3-axis accelerometer on ADC 0, 1, 2.
 *
 * From discovery on it samples the input every control_ms. Contact = the
 * input is high; released = low for release_ms (parameter, default 50) in a
 * row. Each change is sent to the central control as a TOUCH frame
 * (code 0x24, addr, contact 1/0), and any high sample sets the sticky
 * CC_FLAG_TOUCH in STATUS_REPLY. READ_SENSORS: SENSORS with 4 values, the
 * contact state (0/1) and the accelerometer's x, y, z in ADC counts
 * (512 = 0 g, 170.7 counts per g). It has no gait: SET_GAIT with a gait
 * other than 0 sets CC_FLAG_BAD_GAIT. See docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"

#define TOUCH_INPUT 0u

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM("release_ms", HAL_PARAM_U16, 0, 60000, 50, "released once the input was low this long, ms"),
    HAL_PARAM_END
};

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to, i;
    uint8_t contact = 0;
    uint32_t last_contact_ms = 0;
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
                v[0] = contact;
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
            uint8_t level = hal_gpio_read(TOUCH_INPUT);
            uint8_t was = contact;
            if (level) {
                ca_flags |= CC_FLAG_TOUCH;
                last_contact_ms = now;
                contact = 1;
            } else if (contact && now - last_contact_ms >= release_ms) {
                contact = 0;
            }
            if (contact != was) {
                buf[0] = CC_TOUCH;
                buf[1] = ca_addr;
                buf[2] = contact;
                chain_app_reply(buf, CC_TOUCH_LEN);
            }
        }
    }
}
