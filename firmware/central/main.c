/* Central control firmware.
 *
 * 1. Discovery (paper 4.4): raise Sout, offer addresses 0x20, 0x21, ... by
 *    general call; the module holding the baton (Sin high, no address) takes
 *    it, answers with its type and raises its Sout. Done when our Sin (driven
 *    by the last module's Sout) goes high. Logs "chain: RRRR (4 modules)".
 * 2. Reads the gait parameters, sends SET_GAIT to the modules the gait moves
 *    (gaits 1-7: rotation; 8 inchworm: support and extension, each with its
 *    index; 9 helicoidal drive: helicoidal) and START by general call at
 *    start_ms; STOP at stop_ms.
 * 3. Sleeps on I2C, logging replies (and polling the sensors every poll_ms
 *    if that parameter is set).
 * 4. Elbows (gait 9, parameter elbow_dir_deg >= 0): when the touch module
 *    reports contact, it bends every rotation module toward the turn
 *    (SET_GAIT gait 10) for bend_ms while the helicoidal modules push, then
 *    straightens them.
 * See docs/firmware.md.
 */
#include "hal.h"

#include "chain_commands.h"
#include "fixed_sin.h"
#include "strbuf.h"

#define ENUM_REPLY_TIMEOUT_MS 200u
#define SYNC_SETTLE_MS 2u   /* let Sout reach module 0's Sin before the first offer */
#define LONG_SLEEP_MS 60000UL
#define ROLL_SHIFT_MRAD 1571   /* default shift_mrad of the roll (pi/2); 0 for the others */
#define BIAS_DEFAULT_CDEG 1000 /* default bias_cdeg: yaw offset of the turns */

static uint8_t n_modules;
static uint8_t module_type[CHAIN_MAX_MODULES];
static strbuf sb;
static uint8_t rx[HAL_I2C_DATA_MAX];
static uint8_t log_lines; /* logged since the last wait */
static uint8_t touch_event; /* a TOUCH contact frame came in */

/* every wait goes through these, so that log lines are counted per wait */
static void tick_wait(void)
{
    hal_tick_wait();
    log_lines = 0;
}

static uint8_t wait_event(uint16_t timeout_ms, uint8_t mask)
{
    uint32_t before = hal_millis();
    uint8_t ev = hal_wait_event_ms(timeout_ms, mask);
    if (hal_millis() != before) /* it did wait (it returns at once when a frame is waiting) */
        log_lines = 0;
    return ev;
}

/* log a line; a burst (e.g. many replies at once) is spread over ticks
 * instead of being dropped */
static void log_line(const char *line)
{
    if (log_lines >= HAL_LOG_LINES_PER_WAIT)
        tick_wait();
    hal_log(line);
    log_lines++;
}

static void send_frame(uint8_t addr, const uint8_t *data, uint8_t len)
{
    /* the send queue holds only a few frames per wait: wait a tick when full */
    while (hal_i2c_send(addr, data, len) == HAL_ERR_FULL)
        tick_wait();
}

static void send_code(uint8_t addr, uint8_t code)
{
    uint8_t b = code;
    send_frame(addr, &b, 1);
}

static void log_reply(const uint8_t *buf, uint8_t len)
{
    uint8_t i;
    sb_reset(&sb);
    if (buf[0] == CC_SENSORS && len >= 3u && len == CC_SENSORS_LEN(buf[2])) {
        sb_str(&sb, "sensors ");
        sb_hex8(&sb, buf[1]);
        sb_char(&sb, ':');
        for (i = 0; i < buf[2]; i++) {
            sb_char(&sb, ' ');
            sb_int(&sb, cc_get_i16(buf + 3u + 2u * i));
        }
    } else if (buf[0] == CC_STATUS_REPLY && len == CC_STATUS_REPLY_LEN) {
        sb_str(&sb, "status ");
        sb_hex8(&sb, buf[1]);
        sb_str(&sb, ": type=");
        sb_int(&sb, buf[2]);
        sb_str(&sb, " state=");
        sb_int(&sb, buf[3]);
        sb_str(&sb, " gait=");
        sb_int(&sb, buf[4]);
        sb_str(&sb, " flags=");
        sb_hex8(&sb, buf[5]);
    } else if (buf[0] == CC_TOUCH && len == CC_TOUCH_LEN) {
        sb_str(&sb, "touch ");
        sb_hex8(&sb, buf[1]);
        sb_str(&sb, buf[2] ? ": contact" : ": released");
        if (buf[2])
            touch_event = 1;
    } else if (buf[0] == CC_ENUM_REPLY || buf[0] == CC_ENUM_OFFER) {
        return; /* late discovery traffic */
    } else {
        sb_str(&sb, "unexpected frame code ");
        sb_hex8(&sb, buf[0]);
        sb_str(&sb, " len ");
        sb_int(&sb, len);
    }
    log_line(sb.buf);
}

static void log_int(const char *prefix, uint32_t v)
{
    sb_reset(&sb);
    sb_str(&sb, prefix);
    sb_int(&sb, (int32_t)v);
    log_line(sb.buf);
}

/* ---- discovery ------------------------------------------------------------ */

/* wait up to ENUM_REPLY_TIMEOUT_MS for ENUM_REPLY from addr; 1 = got it
 * (type stored), 0 = no reply. *closed is set when our Sin is high. */
static uint8_t await_enum_reply(uint8_t addr, uint8_t *closed)
{
    uint32_t deadline = hal_millis() + ENUM_REPLY_TIMEOUT_MS;
    uint8_t len, to;

    for (;;) {
        uint32_t now;
        while (hal_i2c_receive(rx, sizeof rx, &len, &to) == HAL_OK) {
            if (len == CC_ENUM_REPLY_LEN && rx[0] == CC_ENUM_REPLY && rx[1] == addr) {
                module_type[n_modules] = rx[2];
                return 1;
            }
        }
        *closed = hal_sync_read_sin();
        if (*closed)
            return 0; /* the ring closed: nobody is left to take addr */
        now = hal_millis();
        if ((int32_t)(now - deadline) >= 0)
            return 0;
        (void)wait_event((uint16_t)(deadline - now), HAL_EV_I2C | HAL_EV_SIN_EDGE);
    }
}

static void discover(void)
{
    uint8_t offer[CC_ENUM_OFFER_LEN];
    uint8_t i, addr, closed = 0;

    n_modules = 0;
    hal_sync_write_sout(1);
    hal_delay_ms(SYNC_SETTLE_MS);
    log_lines = 0;
    for (;;) {
        if (hal_sync_read_sin())
            break; /* the baton came back: chain complete */
        if (n_modules >= CHAIN_MAX_MODULES) {
            log_line("discovery: too many modules, stopping");
            break;
        }
        addr = (uint8_t)(CHAIN_FIRST_MODULE_ADDR + n_modules);
        offer[0] = CC_ENUM_OFFER;
        offer[1] = addr;
        send_frame(HAL_I2C_GENERAL_CALL, offer, CC_ENUM_OFFER_LEN);
        if (await_enum_reply(addr, &closed)) {
            n_modules++;
            continue;
        }
        if (!closed) {
            sb_reset(&sb);
            sb_str(&sb, "discovery: no reply at position ");
            sb_int(&sb, n_modules);
            sb_str(&sb, " (address ");
            sb_hex8(&sb, addr);
            sb_str(&sb, ") within 200 ms; continuing with ");
            sb_int(&sb, n_modules);
            sb_str(&sb, " modules");
            log_line(sb.buf);
        }
        break;
    }

    sb_reset(&sb);
    sb_str(&sb, "chain: ");
    for (i = 0; i < n_modules; i++)
        sb_char(&sb, cc_type_letter(module_type[i]));
    if (n_modules != 0)
        sb_char(&sb, ' ');
    sb_char(&sb, '(');
    sb_int(&sb, n_modules);
    sb_str(&sb, " modules)");
    log_line(sb.buf);
}

/* ---- gait --------------------------------------------------------------- */

static int32_t param_clamped(const char *name, int32_t def, int32_t lo, int32_t hi)
{
    int32_t v = hal_param(name, def);
    if (v < lo)
        return lo;
    if (v > hi)
        return hi;
    return v;
}

static void send_gait(uint8_t gait, int16_t amp, int16_t omega, int16_t phase, uint8_t axis,
                      int16_t posture, int16_t amp2, int16_t shift, int16_t bias)
{
    uint8_t f[CC_SET_GAIT_LEN];
    uint8_t i;

    f[0] = CC_SET_GAIT;
    f[CC_GAIT_OFF_GAIT] = gait;
    cc_put_i16(f + CC_GAIT_OFF_AMP, amp);
    cc_put_i16(f + CC_GAIT_OFF_OMEGA, omega);
    cc_put_i16(f + CC_GAIT_OFF_PHASE, phase);
    f[CC_GAIT_OFF_AXIS] = axis;
    cc_put_i16(f + CC_GAIT_OFF_POSTURE, posture);
    cc_put_i16(f + CC_GAIT_OFF_AMP2, amp2);
    cc_put_i16(f + CC_GAIT_OFF_SHIFT, shift);
    cc_put_i16(f + CC_GAIT_OFF_BIAS, bias);
    for (i = 0; i < n_modules; i++)
        if (module_type[i] == MT_ROTATION)
            send_frame((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), f, CC_SET_GAIT_LEN);
}

/* gait 9: the screw command (per mille) to every helicoidal module */
static void send_helicoidal(int16_t drive_pm)
{
    uint8_t f[CC_SET_GAIT_LEN];
    uint8_t i;

    for (i = 0; i < CC_SET_GAIT_LEN; i++)
        f[i] = 0;
    f[0] = CC_SET_GAIT;
    f[CC_GAIT_OFF_GAIT] = GAIT_HELICOIDAL;
    cc_put_i16(f + CC_GAIT_OFF_DRIVE, drive_pm);
    for (i = 0; i < n_modules; i++)
        if (module_type[i] == MT_HELICOIDAL)
            send_frame((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), f, CC_SET_GAIT_LEN);
}

/* gait 8: every support and extension gets the schedule and its index
 * (supports and extensions counted separately, head first) */
static void send_inchworm(int16_t grip, int16_t step, int16_t stroke)
{
    uint8_t f[CC_SET_GAIT_LEN];
    uint8_t i, n_sup = 0, k_sup = 0, k_ext = 0;

    for (i = 0; i < n_modules; i++)
        if (module_type[i] == MT_SUPPORT)
            n_sup++;
    for (i = 0; i < CC_SET_GAIT_LEN; i++)
        f[i] = 0;
    f[0] = CC_SET_GAIT;
    f[CC_GAIT_OFF_GAIT] = GAIT_INCHWORM;
    cc_put_i16(f + CC_GAIT_OFF_GRIP, grip);
    cc_put_i16(f + CC_GAIT_OFF_STEP, step);
    f[CC_GAIT_OFF_NSUP] = n_sup;
    cc_put_i16(f + CC_GAIT_OFF_STROKE, stroke);
    for (i = 0; i < n_modules; i++) {
        if (module_type[i] == MT_SUPPORT)
            cc_put_i16(f + CC_GAIT_OFF_INDEX, (int16_t)k_sup++);
        else if (module_type[i] == MT_EXTENSION)
            cc_put_i16(f + CC_GAIT_OFF_INDEX, (int16_t)k_ext++);
        else
            continue;
        send_frame((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), f, CC_SET_GAIT_LEN);
    }
}

/* gait 10 to every rotation module: hold pitch and yaw (cdeg) */
static void send_bend(int16_t pitch, int16_t yaw)
{
    uint8_t f[CC_SET_GAIT_LEN];
    uint8_t i;

    for (i = 0; i < CC_SET_GAIT_LEN; i++)
        f[i] = 0;
    f[0] = CC_SET_GAIT;
    f[CC_GAIT_OFF_GAIT] = GAIT_BEND;
    cc_put_i16(f + CC_GAIT_OFF_BEND_PITCH, pitch);
    cc_put_i16(f + CC_GAIT_OFF_BEND_YAW, yaw);
    for (i = 0; i < n_modules; i++)
        if (module_type[i] == MT_ROTATION)
            send_frame((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), f, CC_SET_GAIT_LEN);
}

static void drain_replies(void)
{
    uint8_t len, to;
    while (hal_i2c_receive(rx, sizeof rx, &len, &to) == HAL_OK)
        if (len != 0)
            log_reply(rx, len);
}

/* sleep until hal_millis() >= until_ms, handling replies */
static void sleep_until(uint32_t until_ms)
{
    for (;;) {
        uint32_t now = hal_millis();
        uint32_t left;
        drain_replies();
        if ((int32_t)(now - until_ms) >= 0)
            return;
        left = until_ms - now;
        (void)wait_event((uint16_t)(left > LONG_SLEEP_MS ? LONG_SLEEP_MS : left), HAL_EV_I2C);
    }
}

int main(void)
{
    uint8_t gait, axis, started = 0, stopped = 0, i;
    int16_t amp, omega, phase, posture, amp2, shift, bias;
    int16_t drive_pm, step, grip, stroke;
    uint32_t start_ms, stop_ms, poll_ms, next_poll = 0;
    int16_t elbow_dir, bend, bend_pitch = 0, bend_yaw = 0;
    uint16_t bend_ms;
    uint8_t bending = 0, bent_once = 0;
    uint32_t bend_end = 0;

    hal_init();
    hal_i2c_set_address(CHAIN_CENTRAL_ADDR);
    discover();

    gait = (uint8_t)param_clamped("gait", GAIT_FORWARD, 0, 255);
    amp = (int16_t)param_clamped("amplitude_cdeg", 4000, 0, HAL_SERVO_CDEG_MAX);
    omega = (int16_t)param_clamped("omega_mrad_s", 6000, -32767, 32767);
    phase = (int16_t)param_clamped("phase_mrad", 1000, -32767, 32767);
    axis = (uint8_t)param_clamped("axis", CC_AXIS_PITCH, CC_AXIS_PITCH, CC_AXIS_YAW);
    posture = (int16_t)param_clamped("posture_cdeg", 0, -CC_QUARTER_TURN_CDEG, CC_QUARTER_TURN_CDEG);
    /* the two-axis gaits and the turns (docs/firmware.md) */
    amp2 = (int16_t)param_clamped("amplitude2_cdeg", amp, 0, HAL_SERVO_CDEG_MAX);
    shift = (int16_t)param_clamped("shift_mrad", gait == GAIT_ROLL ? ROLL_SHIFT_MRAD : 0,
                                   -32767, 32767);
    bias = (int16_t)param_clamped("bias_cdeg", BIAS_DEFAULT_CDEG, 0, CC_QUARTER_TURN_CDEG);
    /* gait 9 (helicoidal drive) and gait 8 (inchworm) */
    drive_pm = (int16_t)param_clamped("drive_permille", 1000, -1000, 1000);
    step = (int16_t)param_clamped("step_ms", 1000, 40, 30000);
    grip = (int16_t)param_clamped("grip_cdeg", CC_QUARTER_TURN_CDEG, 0, CC_QUARTER_TURN_CDEG);
    stroke = (int16_t)param_clamped("stroke_um", 15000, 0, 15000);
    start_ms = (uint32_t)param_clamped("start_ms", 0, 0, 0x7FFFFFFFL);
    stop_ms = (uint32_t)param_clamped("stop_ms", 0, 0, 0x7FFFFFFFL);
    poll_ms = (uint32_t)param_clamped("poll_ms", 0, 0, 60000L);
    /* elbows: which way the pipe turns, relative to the chain (0 up, 90 left,
     * 180 down, 270 right; -1 = off), how far and how long to bend */
    elbow_dir = (int16_t)param_clamped("elbow_dir_deg", -1, -1, 359);
    bend = (int16_t)param_clamped("bend_cdeg", 4500, 0, CC_QUARTER_TURN_CDEG);
    bend_ms = (uint16_t)param_clamped("bend_ms", 1500, 0, 30000L);
    if (elbow_dir >= 0) {
        /* direction in mrad = deg * 17.453; a positive pitch bends the
         * chain up, a negative yaw to the left (as the turn gait's offset;
         * measured in the simulator, docs/firmware.md) */
        int32_t d = (int32_t)elbow_dir * 17453L / 1000L;
        bend_pitch = fs_scale(bend, fs_cos_mrad(d));
        bend_yaw = (int16_t)-fs_scale(bend, fs_sin_mrad(d));
    }

    sb_reset(&sb);
    sb_str(&sb, "gait: code=");
    sb_int(&sb, gait);
    sb_str(&sb, " amp_cdeg=");
    sb_int(&sb, amp);
    sb_str(&sb, " omega_mrad_s=");
    sb_int(&sb, omega);
    sb_str(&sb, " phase_mrad=");
    sb_int(&sb, phase);
    sb_str(&sb, " axis=");
    sb_int(&sb, axis);
    sb_str(&sb, " posture_cdeg=");
    sb_int(&sb, posture);
    log_line(sb.buf);
    if (gait == GAIT_HELICOIDAL) {
        log_int("gait: drive_permille=", (uint32_t)(int32_t)drive_pm);
    } else if (gait == GAIT_INCHWORM) {
        sb_reset(&sb);
        sb_str(&sb, "gait: step_ms=");
        sb_int(&sb, step);
        sb_str(&sb, " grip_cdeg=");
        sb_int(&sb, grip);
        sb_str(&sb, " stroke_um=");
        sb_int(&sb, stroke);
        log_line(sb.buf);
        if (elbow_dir >= 0) {
            sb_reset(&sb);
            sb_str(&sb, "elbow: dir_deg=");
            sb_int(&sb, elbow_dir);
            sb_str(&sb, " pitch_cdeg=");
            sb_int(&sb, bend_pitch);
            sb_str(&sb, " yaw_cdeg=");
            sb_int(&sb, bend_yaw);
            sb_str(&sb, " bend_ms=");
            sb_int(&sb, bend_ms);
            log_line(sb.buf);
        }
    } else if (gait >= GAIT_TURN_LEFT) {
        sb_reset(&sb);
        sb_str(&sb, "gait: amp2_cdeg=");
        sb_int(&sb, amp2);
        sb_str(&sb, " shift_mrad=");
        sb_int(&sb, shift);
        sb_str(&sb, " bias_cdeg=");
        sb_int(&sb, bias);
        log_line(sb.buf);
    }

    sleep_until(start_ms);
    if (gait != GAIT_NONE && n_modules != 0) {
        if (gait == GAIT_HELICOIDAL)
            send_helicoidal(drive_pm);
        else if (gait == GAIT_INCHWORM)
            send_inchworm(grip, step, stroke);
        else
            send_gait(gait, amp, omega, phase, axis, posture, amp2, shift, bias);
        send_code(HAL_I2C_GENERAL_CALL, CC_START); /* same tick for every module */
        started = 1;
        log_int("start at ms ", hal_millis());
    }
    if (poll_ms != 0)
        next_poll = hal_millis() + poll_ms;

    for (;;) {
        uint32_t now, wake = 0, left;
        uint8_t have_wake = 0;

        drain_replies();
        now = hal_millis();
        if (touch_event) {
            touch_event = 0;
            /* a contact while bent, or within bend_ms after straightening
             * (the head meeting the outgoing leg's wall), is the same elbow */
            if (started && !stopped && gait == GAIT_HELICOIDAL && elbow_dir >= 0 && !bending &&
                (!bent_once || (int32_t)(now - bend_end) >= (int32_t)bend_ms)) {
                send_bend(bend_pitch, bend_yaw);
                log_int("elbow: bend at ms ", now);
                bending = 1;
                bent_once = 1;
                bend_end = now + bend_ms;
            }
        }
        if (bending) {
            if (stopped) {
                bending = 0; /* STOP has straightened them */
            } else if ((int32_t)(now - bend_end) >= 0) {
                send_bend(0, 0);
                bending = 0;
                log_int("elbow: straight at ms ", now);
            } else {
                wake = bend_end;
                have_wake = 1;
            }
        }
        if (started && !stopped && stop_ms != 0) {
            if ((int32_t)(now - stop_ms) >= 0) {
                send_code(HAL_I2C_GENERAL_CALL, CC_STOP);
                stopped = 1;
                log_int("stop at ms ", now);
            } else if (!have_wake || (int32_t)(stop_ms - wake) < 0) {
                wake = stop_ms;
                have_wake = 1;
            }
        }
        if (poll_ms != 0) {
            if ((int32_t)(now - next_poll) >= 0) {
                for (i = 0; i < n_modules; i++)
                    send_code((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), CC_READ_SENSORS);
                next_poll += poll_ms;
                if ((int32_t)(now - next_poll) >= 0)
                    next_poll = now + poll_ms;
            }
            if (!have_wake || (int32_t)(next_poll - wake) < 0)
                wake = next_poll;
            have_wake = 1;
        }
        left = have_wake ? wake - now : LONG_SLEEP_MS;
        if (left > LONG_SLEEP_MS)
            left = LONG_SLEEP_MS;
        if (left == 0)
            left = 1;
        (void)wait_event((uint16_t)left, HAL_EV_I2C);
    }
}
