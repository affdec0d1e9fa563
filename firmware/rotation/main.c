/* Rotation module firmware (MICROTUB snake-like rotation module).
 *
 * Servo 0 = pitch, servo 1 = yaw. After discovery it sleeps on I2C and, while
 * a gait runs, wakes every control_ms to set its servos (t = ms since START,
 * k = chain position = address - 0x20, P(k) = the zig-zag posture):
 *
 *   forward/backward  axis = A sin(w t + s k phi), other = P(k)   (s = +1 / -1)
 *   turn left/right   the same with s = +1, and yaw += -bias / +bias
 *   roll, lat. shift  pitch = A sin(w t + k phi), yaw = A2 sin(w t + k phi + shift)
 *   rotate            pitch = A sin(w t + 2 k phi), yaw = A2 sin(w t + k phi + shift)
 *   bend (gait 10)    pitch, yaw = the frame's fixed angles, held from the
 *                     SET_GAIT on (no START needed): elbow negotiation
 *   limp (gait 12)    both servos released from the SET_GAIT on (no pulses:
 *                     the joints follow the pipe) until the next gait
 *
 * See docs/firmware.md. Integer arithmetic only.
 */
#include "hal.h"

#include "chain_app.h"
#include "chain_commands.h"
#include "gait.h"
#include "strbuf.h"

#define SERVO_PITCH 0u
#define SERVO_YAW 1u

const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10), /* the real modules used about 15 ms */
    HAL_PARAM_END
};

/* the gait last set by SET_GAIT (its code is ca_gait; chain_app.h) */
static int16_t amp_cdeg;
static int16_t omega_mrad_s;
static int16_t phase_mrad;
static uint8_t axis = CC_AXIS_PITCH;
static int16_t posture_cdeg; /* zig-zag of the other axis, CC_GAIT_OFF_POSTURE */
static int16_t amp2_cdeg;    /* yaw wave of the two-axis gaits, CC_GAIT_OFF_AMP2 */
static int16_t shift_mrad;   /* yaw wave's phase relative to the pitch wave */
static int16_t bias_cdeg;    /* yaw offset of the turns, CC_GAIT_OFF_BIAS */
static int16_t bend_pitch_cdeg; /* gait 10 */
static int16_t bend_yaw_cdeg;

static strbuf sb;

static void hold_straight(void)
{
    chain_app_servo(SERVO_PITCH, 0);
    chain_app_servo(SERVO_YAW, 0);
}

/* this module's share of the zig-zag posture (CC_GAIT_OFF_POSTURE) */
static int16_t posture_angle(void)
{
    if (ca_pos == 0)
        return (int16_t)(posture_cdeg / 2);
    return (ca_pos & 1u) ? (int16_t)-posture_cdeg : posture_cdeg;
}

static uint8_t gait_supported(uint8_t g)
{
    return g <= GAIT_LATERAL_SHIFT || g == GAIT_BEND || g == GAIT_LIMP; /* 0 none .. 7 lateral shift, 10 bend, 12 limp */
}

static int16_t clamp_i16(int32_t v, int16_t lim)
{
    if (v > lim)
        return lim;
    if (v < -lim)
        return (int16_t)-lim;
    return (int16_t)v;
}

static void control_step(void)
{
    uint32_t t = chain_app_clock_ms();
    /* k * phase (|k * phase| < 32 * 32768: 32 bits) */
    int32_t offset = (int32_t)ca_pos * (int32_t)phase_mrad;
    int16_t pitch, yaw;

    if (ca_gait == GAIT_BEND) {
        pitch = bend_pitch_cdeg;
        yaw = bend_yaw_cdeg;
    } else if (ca_gait == GAIT_ROLL || ca_gait == GAIT_ROTATE || ca_gait == GAIT_LATERAL_SHIFT) {
        /* two waves of the same omega; rotate: the pitch wave has twice the
         * yaw wave's phase step */
        pitch = gait_angle_cdeg(amp_cdeg, omega_mrad_s, t,
                                ca_gait == GAIT_ROTATE ? offset * 2 : offset);
        yaw = gait_angle_cdeg(amp2_cdeg, omega_mrad_s, t, offset + shift_mrad);
    } else {
        /* forward, backward, turns: one wave on the chosen axis, the zig-zag
         * posture on the other; the wave travels the other way for backward */
        int16_t wave;
        if (ca_gait == GAIT_BACKWARD)
            offset = -offset;
        wave = gait_angle_cdeg(amp_cdeg, omega_mrad_s, t, offset);
        if (axis == CC_AXIS_YAW) {
            yaw = wave;
            pitch = posture_angle();
        } else {
            pitch = wave;
            yaw = posture_angle();
        }
        /* a negative yaw offset bends the chain so that it crawls to the left */
        if (ca_gait == GAIT_TURN_LEFT)
            yaw = clamp_i16((int32_t)yaw - bias_cdeg, HAL_SERVO_CDEG_MAX);
        else if (ca_gait == GAIT_TURN_RIGHT)
            yaw = clamp_i16((int32_t)yaw + bias_cdeg, HAL_SERVO_CDEG_MAX);
    }
    chain_app_servo(SERVO_PITCH, pitch);
    chain_app_servo(SERVO_YAW, yaw);
}

static void stop_gait(void)
{
    ca_running = 0;
    hold_straight();
}

static void start_gait(void)
{
    if (ca_gait == GAIT_NONE || !gait_supported(ca_gait)) {
        if (ca_gait != GAIT_NONE) {
            ca_flags |= CC_FLAG_BAD_GAIT;
            sb_reset(&sb);
            sb_str(&sb, "start: gait ");
            sb_int(&sb, ca_gait);
            sb_str(&sb, " not supported by rotation module");
            hal_log(sb.buf);
        }
        stop_gait();
        return;
    }
    if (ca_gait == GAIT_LIMP)
        return; /* a START to the whole chain (e.g. the supports' inchworm) leaves a limp module limp */
    ca_running = 1;
    chain_app_clock_start(); /* first step now */
}

static void set_gait(const uint8_t *buf)
{
    ca_gait = buf[CC_GAIT_OFF_GAIT];
    if (ca_gait == GAIT_BEND) {
        /* a fixed posture, taken at once (the chain keeps moving) */
        bend_pitch_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_BEND_PITCH), CC_QUARTER_TURN_CDEG);
        bend_yaw_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_BEND_YAW), CC_QUARTER_TURN_CDEG);
        if (!ca_running) {
            ca_running = 1;
            chain_app_clock_start();
        }
        chain_app_step_now(); /* set the servos on the next pass */
        return;
    }
    if (ca_gait == GAIT_LIMP) {
        ca_running = 0;
        (void)hal_servo_release(SERVO_PITCH);
        (void)hal_servo_release(SERVO_YAW);
        return;
    }
    amp_cdeg = cc_get_i16(buf + CC_GAIT_OFF_AMP);
    omega_mrad_s = cc_get_i16(buf + CC_GAIT_OFF_OMEGA);
    phase_mrad = cc_get_i16(buf + CC_GAIT_OFF_PHASE);
    axis = buf[CC_GAIT_OFF_AXIS];
    posture_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_POSTURE), CC_QUARTER_TURN_CDEG);
    if (amp_cdeg < 0)
        amp_cdeg = (int16_t)-amp_cdeg;
    if (amp_cdeg > HAL_SERVO_CDEG_MAX)
        amp_cdeg = HAL_SERVO_CDEG_MAX;
    amp2_cdeg = cc_get_i16(buf + CC_GAIT_OFF_AMP2);
    amp2_cdeg = clamp_i16(amp2_cdeg < 0 ? -(int32_t)amp2_cdeg : amp2_cdeg, HAL_SERVO_CDEG_MAX);
    shift_mrad = cc_get_i16(buf + CC_GAIT_OFF_SHIFT);
    bias_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_BIAS), CC_QUARTER_TURN_CDEG);
    if (axis > CC_AXIS_YAW) {
        axis = CC_AXIS_PITCH;
        ca_flags |= CC_FLAG_BAD_GAIT;
    }
    if (!gait_supported(ca_gait))
        ca_flags |= CC_FLAG_BAD_GAIT;
    if (ca_gait == GAIT_NONE)
        stop_gait();
}

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to, i, n;
    int16_t v[4];

    hal_init();
    hold_straight();
    chain_app_init(MT_ROTATION);

    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            switch (chain_app_filter(buf, len, to)) {
            case CC_SET_GAIT:
                set_gait(buf);
                break;
            case CC_START:
                start_gait();
                break;
            case CC_STOP:
                stop_gait();
                break;
            case CC_READ_SENSORS:
                n = hal_servo_count();
                if (n > HAL_SERVOS_MAX)
                    n = HAL_SERVOS_MAX;
                for (i = 0; i < n; i++)
                    v[i] = hal_servo_angle_cdeg(i);
                chain_app_sensors(v, n);
                break;
            default:
                break;
            }
        }
        if (chain_app_wait(ca_running))
            control_step();
    }
}
