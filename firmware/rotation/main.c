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
 *
 * See docs/firmware.md. Integer arithmetic only.
 */
#include "hal.h"

#include "chain_commands.h"
#include "chain_module.h"
#include "gait.h"
#include "strbuf.h"

#define IDLE_SLEEP_MS 60000u
#define CONTROL_MS_DEFAULT 10
#define SERVO_PITCH 0u
#define SERVO_YAW 1u

static uint8_t my_addr;
static uint8_t my_pos; /* k */
static uint16_t control_ms;

/* the gait last set by SET_GAIT */
static uint8_t gait = GAIT_NONE;
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

static uint8_t running;
static uint32_t t0_ms;        /* hal_millis() at START */
static uint32_t next_step_ms; /* next control step */
static uint8_t flags;         /* CC_FLAG_*, cleared by STATUS */

static strbuf sb;

static void set_servo(uint8_t servo, int16_t cdeg)
{
    if (servo >= hal_servo_count())
        return;
    if (setspangle(servo, cdeg) != HAL_OK)
        flags |= CC_FLAG_SERVO;
}

static void hold_straight(void)
{
    set_servo(SERVO_PITCH, 0);
    set_servo(SERVO_YAW, 0);
}

/* this module's share of the zig-zag posture (CC_GAIT_OFF_POSTURE) */
static int16_t posture_angle(void)
{
    if (my_pos == 0)
        return (int16_t)(posture_cdeg / 2);
    return (my_pos & 1u) ? (int16_t)-posture_cdeg : posture_cdeg;
}

static uint8_t gait_supported(uint8_t g)
{
    return g <= GAIT_LATERAL_SHIFT || g == GAIT_BEND; /* 0 none .. 7 lateral shift, 10 bend */
}

static int16_t clamp_i16(int32_t v, int16_t lim)
{
    if (v > lim)
        return lim;
    if (v < -lim)
        return (int16_t)-lim;
    return (int16_t)v;
}

static void control_step(uint32_t now_ms)
{
    uint32_t t = now_ms - t0_ms;
    /* k * phase (|k * phase| < 32 * 32768: 32 bits) */
    int32_t offset = (int32_t)my_pos * (int32_t)phase_mrad;
    int16_t pitch, yaw;

    if (gait == GAIT_BEND) {
        pitch = bend_pitch_cdeg;
        yaw = bend_yaw_cdeg;
    } else if (gait == GAIT_ROLL || gait == GAIT_ROTATE || gait == GAIT_LATERAL_SHIFT) {
        /* two waves of the same omega; rotate: the pitch wave has twice the
         * yaw wave's phase step */
        pitch = gait_angle_cdeg(amp_cdeg, omega_mrad_s, t,
                                gait == GAIT_ROTATE ? offset * 2 : offset);
        yaw = gait_angle_cdeg(amp2_cdeg, omega_mrad_s, t, offset + shift_mrad);
    } else {
        /* forward, backward, turns: one wave on the chosen axis, the zig-zag
         * posture on the other; the wave travels the other way for backward */
        int16_t wave;
        if (gait == GAIT_BACKWARD)
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
        if (gait == GAIT_TURN_LEFT)
            yaw = clamp_i16((int32_t)yaw - bias_cdeg, 18000);
        else if (gait == GAIT_TURN_RIGHT)
            yaw = clamp_i16((int32_t)yaw + bias_cdeg, 18000);
    }
    set_servo(SERVO_PITCH, pitch);
    set_servo(SERVO_YAW, yaw);
}

static void stop_gait(void)
{
    running = 0;
    hold_straight();
}

static void start_gait(void)
{
    if (gait == GAIT_NONE || !gait_supported(gait)) {
        if (gait != GAIT_NONE) {
            flags |= CC_FLAG_BAD_GAIT;
            sb_reset(&sb);
            sb_str(&sb, "start: gait ");
            sb_int(&sb, gait);
            sb_str(&sb, " not supported by rotation module");
            hal_log(sb.buf);
        }
        stop_gait();
        return;
    }
    running = 1;
    t0_ms = hal_millis();
    next_step_ms = t0_ms; /* first step now */
}

static void reply(const uint8_t *data, uint8_t len)
{
    /* replies are rare; if the queue is full this tick, wait one tick */
    while (hal_i2c_send(CHAIN_CENTRAL_ADDR, data, len) == HAL_ERR_FULL)
        hal_tick_wait();
}

static void handle_frame(const uint8_t *buf, uint8_t len, uint8_t to)
{
    uint8_t out[CC_SENSORS_LEN(4)];
    uint8_t i, n;

    if (len == 0 || (to != my_addr && to != HAL_I2C_GENERAL_CALL))
        return;
    switch (buf[0]) {
    case CC_ENUM_OFFER:
        return; /* already addressed */
    case CC_SET_GAIT:
        if (len != CC_SET_GAIT_LEN)
            break;
        gait = buf[CC_GAIT_OFF_GAIT];
        if (gait == GAIT_BEND) {
            /* a fixed posture, taken at once (the chain keeps moving) */
            bend_pitch_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_BEND_PITCH), 9000);
            bend_yaw_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_BEND_YAW), 9000);
            if (!running) {
                running = 1;
                t0_ms = hal_millis();
            }
            next_step_ms = hal_millis(); /* set the servos on the next pass */
            return;
        }
        amp_cdeg = cc_get_i16(buf + CC_GAIT_OFF_AMP);
        omega_mrad_s = cc_get_i16(buf + CC_GAIT_OFF_OMEGA);
        phase_mrad = cc_get_i16(buf + CC_GAIT_OFF_PHASE);
        axis = buf[CC_GAIT_OFF_AXIS];
        posture_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_POSTURE), 9000);
        if (amp_cdeg < 0)
            amp_cdeg = (int16_t)-amp_cdeg;
        if (amp_cdeg > 18000)
            amp_cdeg = 18000;
        amp2_cdeg = cc_get_i16(buf + CC_GAIT_OFF_AMP2);
        amp2_cdeg = clamp_i16(amp2_cdeg < 0 ? -(int32_t)amp2_cdeg : amp2_cdeg, 18000);
        shift_mrad = cc_get_i16(buf + CC_GAIT_OFF_SHIFT);
        bias_cdeg = clamp_i16(cc_get_i16(buf + CC_GAIT_OFF_BIAS), 9000);
        if (axis > CC_AXIS_YAW) {
            axis = CC_AXIS_PITCH;
            flags |= CC_FLAG_BAD_GAIT;
        }
        if (!gait_supported(gait))
            flags |= CC_FLAG_BAD_GAIT;
        if (gait == GAIT_NONE)
            stop_gait();
        return;
    case CC_START:
        if (len != CC_START_LEN)
            break;
        start_gait();
        return;
    case CC_STOP:
        if (len != CC_STOP_LEN)
            break;
        stop_gait();
        return;
    case CC_READ_SENSORS:
        if (len != CC_READ_SENSORS_LEN || to != my_addr)
            break;
        n = hal_servo_count();
        if (n > 4u)
            n = 4u;
        out[0] = CC_SENSORS;
        out[1] = my_addr;
        out[2] = n;
        for (i = 0; i < n; i++)
            cc_put_i16(out + 3u + 2u * i, hal_servo_angle_cdeg(i));
        reply(out, (uint8_t)CC_SENSORS_LEN(n));
        return;
    case CC_STATUS:
        if (len != CC_STATUS_LEN || to != my_addr)
            break;
        out[0] = CC_STATUS_REPLY;
        out[1] = my_addr;
        out[2] = MT_ROTATION;
        out[3] = running ? CC_STATE_RUNNING : CC_STATE_IDLE;
        out[4] = gait;
        out[5] = flags;
        flags = 0;
        reply(out, CC_STATUS_REPLY_LEN);
        return;
    default:
        break;
    }
    flags |= CC_FLAG_BAD_FRAME;
}

int main(void)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to;
    int32_t p;

    hal_init();
    p = hal_param("control_ms", CONTROL_MS_DEFAULT);
    if (p < 1)
        p = 1;
    if (p > 1000)
        p = 1000;
    control_ms = (uint16_t)p;

    hold_straight();
    my_addr = chain_module_discover(MT_ROTATION);
    my_pos = (uint8_t)(my_addr - CHAIN_FIRST_MODULE_ADDR);

    for (;;) {
        uint32_t now;
        uint16_t sleep_ms;

        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK)
            handle_frame(buf, len, to);

        now = hal_millis();
        if (running) {
            if ((int32_t)(now - next_step_ms) >= 0) {
                control_step(now);
                next_step_ms += control_ms;
                if ((int32_t)(now - next_step_ms) >= 0) /* fell behind: resync */
                    next_step_ms = now + control_ms;
            }
            sleep_ms = (uint16_t)(next_step_ms - now);
        } else {
            sleep_ms = IDLE_SLEEP_MS;
        }
        (void)hal_wait_event_ms(sleep_ms, HAL_EV_I2C);
    }
}
