/* A module program of your own (docs/firmware.md, "Your own program"): a
 * rotation module that takes part in discovery and obeys the central
 * control like fw-rotation, but moves its pitch servo in a triangle wave
 * instead of a sine:
 *
 *   pitch_k(t) = A * tri(w t + k phi)      tri: 0 -> +1 -> -1 -> 0 over a period
 *   yaw_k      = the zig-zag posture P (+P/2 on module 0, -P odd, +P even)
 *
 * A, w, phi, P come in SET_GAIT (gait 1, forward); START starts the clock,
 * STOP or gait 0 straightens the module. Parameter `control_ms` (default 10)
 * is the control period. C99, integers only: it builds for the simulator
 * and for the PIC18F2550 from these same lines. */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"
#include "gait.h"
#include "strbuf.h"

#define QUARTER_MRAD 1571 /* a quarter of the 6283 mrad period */

/* the program's parameters: what a scene may set (docs/firmware.md, "Parameters") */
const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM_END
};

static int16_t amp_cdeg;
static int16_t omega_mrad_s;
static int16_t phase_mrad;
static int16_t posture_cdeg;
static strbuf sb;

/* amp * tri(phase), phase in 0..6282 mrad: +amp at a quarter period, -amp at three */
static int16_t triangle_cdeg(int16_t amp, int16_t phase)
{
    int32_t v;
    if (phase < QUARTER_MRAD)
        v = phase;
    else if (phase < 3 * QUARTER_MRAD)
        v = 2 * QUARTER_MRAD - (int32_t)phase;
    else
        v = (int32_t)phase - 4 * QUARTER_MRAD;
    return (int16_t)(((int32_t)amp * v) / QUARTER_MRAD);
}

static int16_t posture_angle(void)
{
    if (ca_pos == 0)
        return (int16_t)(posture_cdeg / 2);
    return (ca_pos & 1u) ? (int16_t)-posture_cdeg : posture_cdeg;
}

static void straighten(void)
{
    ca_running = 0;
    chain_app_servo(0, 0);
    chain_app_servo(1, 0);
}

static void control_step(void)
{
    int16_t phase = gait_phase_mrad(omega_mrad_s, chain_app_clock_ms(), (int32_t)ca_pos * phase_mrad);
    chain_app_servo(0, triangle_cdeg(amp_cdeg, phase));
    chain_app_servo(1, posture_angle());
}

static void set_gait(const uint8_t *buf)
{
    if (chain_app_take_gait(buf, GAIT_FORWARD) == GAIT_NONE) {
        straighten();
        return;
    }
    amp_cdeg = cc_get_i16(buf + CC_GAIT_OFF_AMP);
    if (amp_cdeg < 0 || amp_cdeg > 9000)
        amp_cdeg = 9000;
    omega_mrad_s = cc_get_i16(buf + CC_GAIT_OFF_OMEGA);
    phase_mrad = cc_get_i16(buf + CC_GAIT_OFF_PHASE);
    posture_cdeg = cc_get_i16(buf + CC_GAIT_OFF_POSTURE);
}

static void start(void)
{
    if (ca_gait != GAIT_FORWARD) {
        straighten();
        return;
    }
    sb_reset(&sb);
    sb_str(&sb, "triangle: start amp_cdeg=");
    sb_int(&sb, amp_cdeg);
    sb_str(&sb, " omega_mrad_s=");
    sb_int(&sb, omega_mrad_s);
    hal_log(sb.buf);
    ca_running = 1;
    chain_app_clock_start();
}

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to;
    int16_t v[2];

    hal_init();
    chain_app_servo(0, 0);
    chain_app_servo(1, 0);
    chain_app_init(MT_ROTATION);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                set_gait(buf);
                break;
            case CC_START:
                start();
                break;
            case CC_STOP:
                straighten();
                break;
            case CC_READ_SENSORS:
                v[0] = hal_servo_angle_cdeg(0);
                v[1] = hal_servo_angle_cdeg(1);
                chain_app_sensors(v, 2);
                break;
            default:
                break;
            }
        }
        if (chain_app_wait(ca_running))
            control_step();
    }
}
