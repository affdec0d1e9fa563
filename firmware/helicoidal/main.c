/* Helicoidal module firmware (paper 3.3.2): a pig body pushed along its axis
 * by a screw drive. Servo 0 = the screw drive: its set-point is the drive
 * command -1..1, which setspangle carries as a servo pulse for the drive's
 * speed controller: -9000..9000 cdeg (1.0 .. 2.0 ms) = full reverse .. full
 * forward, the per mille command x 9. The command spans the whole pulse
 * because a narrow one would not survive the board: per mille / 10 is a
 * pulse 5.6 us either side of 1.5 ms, which the 0.2 us pulse steps round
 * (97.2 % of full speed) and a real controller's dead band would ignore.
 *
 * Gait 9 (helicoidal drive): SET_GAIT carries the command in per mille
 * (CC_GAIT_OFF_DRIVE); from START until STOP (or SET_GAIT gait 0) the screw
 * runs at that command; otherwise it is stopped (command 0). Any other gait
 * code sets CC_FLAG_BAD_GAIT. READ_SENSORS: SENSORS with 2 values, the
 * command in per mille and the screw's supply current in ADC counts (ADC 0).
 * See docs/firmware.md. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"

#define SERVO_SCREW 0u

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM_END
};

static int16_t drive_pm; /* command from SET_GAIT, per mille */

static void set_drive(int16_t pm)
{
    if (pm > 1000)
        pm = 1000;
    if (pm < -1000)
        pm = -1000;
    chain_app_servo(SERVO_SCREW, (int16_t)(pm * 9));
}

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to;
    int16_t v[2];

    hal_init();
    set_drive(0);
    chain_app_init(MT_HELICOIDAL);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                (void)chain_app_take_gait(buf, GAIT_HELICOIDAL);
                drive_pm = cc_get_i16(buf + CC_GAIT_OFF_DRIVE);
                if (ca_gait == GAIT_NONE) {
                    ca_running = 0;
                    set_drive(0);
                } else if (ca_running && ca_gait == GAIT_HELICOIDAL) {
                    set_drive(drive_pm); /* a new command while running */
                }
                break;
            case CC_START:
                ca_running = ca_gait == GAIT_HELICOIDAL;
                set_drive(ca_running ? drive_pm : 0);
                if (ca_gait != GAIT_NONE && !ca_running)
                    hal_log("start: gait not supported by helicoidal module");
                break;
            case CC_STOP:
                ca_running = 0;
                set_drive(0);
                break;
            case CC_READ_SENSORS:
                v[0] = ca_running ? drive_pm : 0;
                v[1] = (int16_t)hal_adc_read(0);
                chain_app_sensors(v, 2);
                break;
            default:
                break;
            }
        }
        (void)chain_app_wait(0);
    }
}
