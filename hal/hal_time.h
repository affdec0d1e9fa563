/** @file
 * Time: the only place where time passes for firmware.
 * Outputs written with other HAL calls take effect at the next wait. */
#ifndef HAL_TIME_H
#define HAL_TIME_H

#include <stdint.h>

/** events hal_wait_event_ms can wake on (bit mask) */
#define HAL_EV_I2C 0x02u      /**< an I2C frame for this module arrived */
#define HAL_EV_SIN_EDGE 0x04u /**< the Sin synchronism line changed level */

/** set up the board (simulator: connect to the physics server); call first */
void hal_init(void);

/** return at the next HAL timer tick (1 ms by default) */
void hal_tick_wait(void);

/** sleep for ms milliseconds; nothing wakes the module earlier */
void hal_delay_ms(uint16_t ms);

/** sleep until one of the events in mask happens or timeout_ms passes;
 * returns the events that happened, 0 on timeout.
 * With HAL_EV_I2C in mask and a received frame not yet read, it returns
 * HAL_EV_I2C at once, without sleeping: no time passes (in the simulator,
 * no tick). Read the frame (hal_i2c_receive) before waiting again, or the
 * loop spins; the simulator then reports the module as hung after
 * --module-timeout, naming this cause. */
uint8_t hal_wait_event_ms(uint16_t timeout_ms, uint8_t mask);

/** milliseconds since start (wraps after ~49 days) */
uint32_t hal_millis(void);

#endif
