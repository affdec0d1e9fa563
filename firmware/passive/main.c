/* Passive module firmware: no actuators and no sensors. It takes part in
 * discovery (type 7) and answers STATUS; START, STOP and SET_GAIT are
 * accepted and do nothing (SET_GAIT with a gait other than 0 sets
 * CC_FLAG_BAD_GAIT); READ_SENSORS gets a SENSORS reply with no values.
 * See docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM_END
};

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to;
    int16_t none[1];

    hal_init();
    chain_app_init(MT_PASSIVE);
    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                (void)chain_app_take_gait(buf, GAIT_NONE);
                break;
            case CC_READ_SENSORS:
                chain_app_sensors(none, 0);
                break;
            default:
                break;
            }
        }
        (void)chain_app_wait(0);
    }
}
