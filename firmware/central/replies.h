/* What the modules send the central control: each reply (SENSORS,
 * STATUS_REPLY, TOUCH, anything unexpected) becomes a log line; a TOUCH
 * contact and its direction, and a helicoidal module's stall, are also kept
 * for the elbow negotiation. */
#ifndef REPLIES_H
#define REPLIES_H

#include <stdint.h>

/* log every received frame */
void replies_drain(void);

/* 1 when a new TOUCH contact (the first closed set after a release) came
 * in since the last call (then cleared); *dir_deg = the obstacle's direction
 * it gave, *up_deg = where up was (in the touch module's frame, degrees;
 * CC_TOUCH_NONE: head-on, or gravity along the axis) */
uint8_t replies_take_touch(int16_t *dir_deg, int16_t *up_deg);

/* 1 when a TOUCH frame had all three switches closed at once (pushed
 * head-on) since the last call, then cleared */
uint8_t replies_take_head_on(void);

/* 1 when a helicoidal module's current (SENSORS, the second value) has been
 * at or above params.stall_counts on two of its replies in a row (each
 * module counted on its own), since the last call: once per stall (a reply
 * of that module below it starts its count again); never when stall_counts
 * is 0 */
uint8_t replies_take_stall(void);

/* the same for params.switch_counts (gait switching, main.c) */
uint8_t replies_take_labour(void);

/* count every module's replies at or above switch_counts from 0 again */
void replies_forget_labour(void);

/* sleep until hal_millis() >= until_ms, logging replies */
void replies_sleep_until(uint32_t until_ms);

#endif
