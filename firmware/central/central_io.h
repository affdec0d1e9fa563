/* The central control's waits, log lines and sends. Every wait goes through
 * here so that log lines are counted per wait: a burst (many replies at
 * once) is spread over ticks, HAL_LOG_LINES_PER_WAIT a wait, instead of being
 * dropped. A send waits a tick while the HAL's queue is full. */
#ifndef CENTRAL_IO_H
#define CENTRAL_IO_H

#include <stdint.h>

#include "hal_i2c.h"
#include "strbuf.h"

/* the line being built; log it with cio_log_line(cio_sb.buf) */
extern strbuf cio_sb;
/* the frame being read (one buffer for the program: SDCC gives every local
 * array RAM of its own) */
extern uint8_t cio_rx[HAL_I2C_DATA_MAX];

void cio_tick_wait(void);
uint8_t cio_wait_event(uint16_t timeout_ms, uint8_t mask); /* hal_wait_event_ms */
/* a wait outside these (discovery's hal_delay_ms) starts a new count */
void cio_new_wait(void);

/* append text, then v in decimal, to cio_sb (one call instead of two: on
 * the PIC every call passing &cio_sb costs code) */
void cio_put(const char *text, int32_t v);

/* append the name of a side, CC_SIDE_* ("up", "left", "down", "right";
 * "none" for any other value) */
void cio_put_side(uint8_t side);

void cio_log_line(const char *line);
void cio_log_int(const char *prefix, uint32_t v); /* prefix, then v as a signed number */

void cio_send(uint8_t addr, const uint8_t *data, uint8_t len);
void cio_send_code(uint8_t addr, uint8_t code); /* a one-byte frame */

#endif
