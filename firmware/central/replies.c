/* Replies from the modules: see replies.h. */
#include "replies.h"

#include "central_io.h"
#include "central_params.h"
#include "chain_commands.h"
#include "discovery.h"
#include "hal.h"

#define LONG_SLEEP_MS 60000UL

static uint8_t touch_contact; /* a new TOUCH contact came in */
static int16_t touch_dir;     /* its obstacle direction */
static int16_t touch_up;      /* where up was */
static uint8_t touch_closed;  /* the cover's switches closed now (from the last TOUCH frame) */
static uint8_t touch_all;     /* every switch closed at once since replies_take_head_on */
/* A helicoidal module's current at or above a threshold on two of its own
 * SENSORS replies in a row: per module, whether its last reply was high and
 * whether its current run has fired; one pending trigger for the main loop. */
#define WATCH_HIGH 1u  /* the module's last reply was at or above */
#define WATCH_TAKEN 2u /* its current run of replies has fired */
typedef struct {
    uint8_t module[CHAIN_MAX_MODULES]; /* WATCH_* bits of each module */
    uint8_t pending;                   /* fired since the last take */
} current_watch;
static current_watch stall_watch;  /* stall_counts: an elbow */
static current_watch switch_watch; /* switch_counts: the screw labours */

static void watch_reply(current_watch *w, uint8_t module, int16_t current, uint16_t threshold)
{
    uint8_t *m = &w->module[module];
    if (current < (int16_t)threshold) {
        *m = 0; /* a reply below ends the run */
        return;
    }
    if (*m == WATCH_HIGH) {
        *m = WATCH_HIGH | WATCH_TAKEN; /* once per run */
        w->pending = 1;
    } else if (*m == 0) {
        *m = WATCH_HIGH;
    }
}

static uint8_t take_watch(current_watch *w)
{
    uint8_t p = w->pending;
    w->pending = 0;
    return p;
}

static void log_reply(const uint8_t *buf, uint8_t len)
{
    uint8_t i;
    sb_reset(&cio_sb);
    if (buf[0] == CC_SENSORS && len >= 3u && len == CC_SENSORS_LEN(buf[2])) {
        sb_str(&cio_sb, "sensors ");
        sb_hex8(&cio_sb, buf[1]);
        sb_char(&cio_sb, ':');
        for (i = 0; i < buf[2]; i++) {
            sb_char(&cio_sb, ' ');
            sb_int(&cio_sb, cc_get_i16(buf + 3u + 2u * i));
        }
        /* a helicoidal module's current (its second value) at stall */
        i = (uint8_t)(buf[1] - CHAIN_FIRST_MODULE_ADDR);
        if (i < chain_n_modules && chain_module_type[i] == MT_HELICOIDAL && buf[2] >= 2u) {
            if (params.stall_counts != 0)
                watch_reply(&stall_watch, i, cc_get_i16(buf + 5u), params.stall_counts);
            if (params.switch_counts != 0)
                watch_reply(&switch_watch, i, cc_get_i16(buf + 5u), params.switch_counts);
        }
    } else if (buf[0] == CC_STATUS_REPLY && len == CC_STATUS_REPLY_LEN) {
        sb_str(&cio_sb, "status ");
        sb_hex8(&cio_sb, buf[1]);
        cio_put(": type=", buf[2]);
        cio_put(" state=", buf[3]);
        cio_put(" gait=", buf[4]);
        sb_str(&cio_sb, " flags=");
        sb_hex8(&cio_sb, buf[5]);
    } else if (buf[0] == CC_TOUCH && len == CC_TOUCH_LEN) {
        int16_t dir = cc_get_i16(buf + CC_TOUCH_OFF_DIR), up = cc_get_i16(buf + CC_TOUCH_OFF_UP);
        uint8_t s = buf[CC_TOUCH_OFF_SIDE];
        sb_str(&cio_sb, "touch ");
        sb_hex8(&cio_sb, buf[1]);
        sb_str(&cio_sb, buf[2] ? ": contact" : ": released");
        if (buf[2]) {
            /* e.g. "touch 02: contact switches=3 dir_deg=60 up_deg=0 side=up" */
            cio_put(" switches=", buf[2]);
            cio_put(" dir_deg=", dir);
            cio_put(" up_deg=", up);
            sb_str(&cio_sb, " side=");
            cio_put_side(s);
            /* a new contact is the first closed set after a release: more
             * switches closing, or some opening, on the same wall is the
             * same contact */
            if (!touch_closed) {
                touch_contact = 1;
                touch_dir = dir;
                touch_up = up;
            }
        }
        touch_closed = buf[2];
        if (buf[2] == 7u)
            touch_all = 1;
    } else if (buf[0] == CC_ENUM_REPLY || buf[0] == CC_ENUM_OFFER) {
        return; /* late discovery traffic */
    } else {
        sb_str(&cio_sb, "unexpected frame code ");
        sb_hex8(&cio_sb, buf[0]);
        cio_put(" len ", len);
    }
    cio_log_line(cio_sb.buf);
}

void replies_drain(void)
{
    uint8_t len, to;
    while (hal_i2c_receive(cio_rx, sizeof cio_rx, &len, &to) == HAL_OK)
        if (len != 0)
            log_reply(cio_rx, len);
}

uint8_t replies_take_touch(int16_t *dir_deg, int16_t *up_deg)
{
    uint8_t t = touch_contact;
    touch_contact = 0;
    *dir_deg = touch_dir;
    *up_deg = touch_up;
    return t;
}

uint8_t replies_take_stall(void)
{
    return take_watch(&stall_watch);
}

uint8_t replies_take_labour(void)
{
    return take_watch(&switch_watch);
}

void replies_forget_labour(void)
{
    uint8_t i;
    for (i = 0; i < CHAIN_MAX_MODULES; i++)
        switch_watch.module[i] = 0;
    switch_watch.pending = 0;
}

uint8_t replies_take_head_on(void)
{
    uint8_t a = touch_all;
    touch_all = 0;
    return a;
}

void replies_sleep_until(uint32_t until_ms)
{
    for (;;) {
        uint32_t now = hal_millis();
        uint32_t left;
        replies_drain();
        if ((int32_t)(now - until_ms) >= 0)
            return;
        left = until_ms - now;
        (void)cio_wait_event((uint16_t)(left > LONG_SLEEP_MS ? LONG_SLEEP_MS : left), HAL_EV_I2C);
    }
}
