/* Central control firmware (fw-central).
 *
 * 1. Discovery (discovery.c): addresses the modules along the sync lines and
 *    logs "chain: RRRR (4 modules)".
 * 2. Reads its parameters (central_params.c) and logs the gait (gaits.c).
 * 3. At start_ms: SET_GAIT to the modules the gait moves (gaits.c), then
 *    START by general call, so that every module starts at the same tick;
 *    STOP at stop_ms.
 * 4. Sleeps on I2C, logging the replies (replies.c), polling the sensors
 *    every poll_ms if that parameter is set, and bending the rotation
 *    modules at elbows (elbow.c): at a touch module's contact, or when the
 *    helicoidal modules stall (stall_counts).
 * 5. Gait switching (switch_counts, paper 6.7): while the helicoidal drive
 *    labours (its current at or above switch_counts on two polls in a row)
 *    the supports and extensions run the inchworm for switch_ms, the screw
 *    still driving; then they let go and the screw is tried alone again.
 *    It waits while an elbow's bend or the supports' hold lasts, and a
 *    stall while the inchworm runs is not taken for an elbow.
 * See docs/firmware.md, "Central control". */
#include "hal.h"

#include "central_io.h"
#include "central_params.h"
#include "chain_commands.h"
#include "discovery.h"
#include "elbow.h"
#include "gaits.h"
#include "replies.h"

#define LONG_SLEEP_MS 60000UL

static uint8_t started, stopped;
static uint32_t next_poll;
static uint8_t inching;     /* gait switching: the inchworm runs until inch_end */
static uint32_t inch_end;

/* SET_GAIT and START, if there is a gait and a module to run it */
static void start(void)
{
    if (params.gait == GAIT_NONE || chain_n_modules == 0)
        return;
    gaits_send();
    cio_send_code(HAL_I2C_GENERAL_CALL, CC_START); /* same tick for every module */
    started = 1;
    cio_log_int("start at ms ", hal_millis());
}

/* READ_SENSORS to every module when a poll is due */
static void poll(uint32_t now)
{
    uint8_t i;
    if ((int32_t)(now - next_poll) >= 0) {
        for (i = 0; i < chain_n_modules; i++)
            cio_send_code((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), CC_READ_SENSORS);
        next_poll += params.poll_ms;
        if ((int32_t)(now - next_poll) >= 0)
            next_poll = now + params.poll_ms;
    }
}

/* gait switching (switch_counts): start the inchworm when the screw
 * labours, end it after switch_ms; not while the elbow steering or the
 * supports' hold lasts (elbow_busy: they would send the supports other
 * gaits), and a labour seen then is dropped. Returns 1 while it runs (wake
 * at inch_end). */
static uint8_t gait_switch(uint32_t now, uint8_t driving, uint8_t elbow_busy)
{
    if (params.switch_counts == 0 || !driving) {
        inching = 0; /* after STOP the supports hold */
        return 0;
    }
    if (!inching) {
        if (!replies_take_labour())
            return 0;
        if (elbow_busy) {
            replies_forget_labour();
            return 0;
        }
        cio_log_int("switch: inchworm at ms ", now);
        gaits_send_inchworm(GAIT_INCHWORM);
        cio_send_code(HAL_I2C_GENERAL_CALL, CC_START); /* one clock for every support and extension */
        inching = 1;
        inch_end = now + params.switch_ms;
    } else if ((int32_t)(now - inch_end) >= 0) {
        gaits_send_none(MT_SUPPORT);
        gaits_send_none(MT_EXTENSION);
        replies_forget_labour();
        inching = 0;
        cio_log_int("switch: helicoidal at ms ", now);
        return 0;
    }
    return 1;
}

/* one pass of the main loop: replies, elbow, stop, poll, then sleep until
 * the earliest of the deadlines or a frame */
static void serve(void)
{
    uint32_t now, wake = 0, left;
    uint8_t have_wake, driving; /* driving: the helicoidal gait runs (started, not stopped) */
    int16_t touch_dir, touch_up;

    replies_drain();
    now = hal_millis();
    driving = started && !stopped && params.gait == GAIT_HELICOIDAL;
    if (replies_take_touch(&touch_dir, &touch_up) && driving)
        elbow_contact(now, touch_dir, touch_up);
    /* a stall while the inchworm runs is the switch's business, not an elbow */
    if (replies_take_stall() && driving && !inching) {
        cio_log_int("elbow: stall at ms ", now);
        elbow_contact(now, CC_TOUCH_NONE, CC_TOUCH_NONE); /* no direction: the given one */
    }
    have_wake = elbow_update(now, stopped, replies_take_head_on());
    if (have_wake)
        wake = elbow_wake;
    if (gait_switch(now, driving, have_wake) && (!have_wake || (int32_t)(inch_end - wake) < 0)) {
        wake = inch_end;
        have_wake = 1;
    }
    if (started && !stopped && params.stop_ms != 0) {
        if ((int32_t)(now - params.stop_ms) >= 0) {
            cio_send_code(HAL_I2C_GENERAL_CALL, CC_STOP);
            stopped = 1;
            cio_log_int("stop at ms ", now);
        } else if (!have_wake || (int32_t)(params.stop_ms - wake) < 0) {
            wake = params.stop_ms;
            have_wake = 1;
        }
    }
    if (params.poll_ms != 0) {
        poll(now);
        if (!have_wake || (int32_t)(next_poll - wake) < 0)
            wake = next_poll;
        have_wake = 1;
    }
    left = have_wake ? wake - now : LONG_SLEEP_MS;
    if (left > LONG_SLEEP_MS)
        left = LONG_SLEEP_MS;
    if (left == 0)
        left = 1;
    (void)cio_wait_event((uint16_t)left, HAL_EV_I2C);
}

int main(void)
{
    hal_init();
    hal_i2c_set_address(CHAIN_CENTRAL_ADDR);
    discovery_run();

    central_params_read();
    elbow_setup();
    gaits_log();
    elbow_log();    /* the steering: given by elbow_dir_deg, sensed, or off */

    replies_sleep_until(params.start_ms);
    start();
    if (params.poll_ms != 0)
        next_poll = hal_millis() + params.poll_ms;
    for (;;)
        serve();
}
