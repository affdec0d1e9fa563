/** @file
 * The part of a module program every module type shares after discovery:
 * the frame filter (addressing, lengths, ENUM_OFFER, STATUS), replies to the
 * central control, the shared gait clock and the control-step timer. Every
 * module program (rotation included) keeps its own main loop and handles
 * SET_GAIT, START, STOP and READ_SENSORS itself. See docs/firmware.md. */
#ifndef CHAIN_APP_H
#define CHAIN_APP_H

#include <stdint.h>

#include "hal_param.h"

/** this module, after chain_app_init */
extern uint8_t ca_addr; /**< I2C address, 0x20 + k */
extern uint8_t ca_pos;  /**< k, chain position */
extern uint8_t ca_type; /**< MT_* */
/** the state STATUS_REPLY reports; the program keeps them current */
extern uint8_t ca_running; /**< 1 while a gait runs */
extern uint8_t ca_gait;    /**< gait last set by SET_GAIT */
extern uint8_t ca_flags;   /**< CC_FLAG_*, cleared when STATUS reads them */
extern uint16_t ca_control_ms; /**< parameter control_ms (1..1000) */

/** the declaration of control_ms, the control period every module program
 * using chain_app has: put it in the program's hal_param_table with the
 * program's own default */
#define CHAIN_APP_PARAM_CONTROL_MS(default_ms) \
    HAL_PARAM("control_ms", HAL_PARAM_U16, 1, 1000, default_ms, "control period, ms")

/** read control_ms (the program declares it: CHAIN_APP_PARAM_CONTROL_MS), run
 * discovery reporting type, set ca_addr/ca_pos */
void chain_app_init(uint8_t type);

/** Check one received frame. Returns its command code when the program must
 * act on it (SET_GAIT, START, STOP, READ_SENSORS, all of the right length and
 * addressed to this module or, START/STOP, to the general call); 0 when it
 * was handled here (STATUS is answered) or must be ignored (not for us,
 * ENUM_OFFER); an unknown code or a wrong length sets CC_FLAG_BAD_FRAME and
 * returns 0. */
uint8_t chain_app_filter(const uint8_t *buf, uint8_t len, uint8_t to);

/** SET_GAIT's gait code into ca_gait; a code other than GAIT_NONE and the
 * module's own `supported` gait sets CC_FLAG_BAD_GAIT. Returns the code. */
uint8_t chain_app_take_gait(const uint8_t *buf, uint8_t supported);

/** send a frame to the central control (waits a tick while the queue is full) */
void chain_app_reply(const uint8_t *data, uint8_t len);

/** SENSORS reply: n (<= 6) signed 16-bit values */
void chain_app_sensors(const int16_t *v, uint8_t n);

/** setspangle that records a refusal in ca_flags (servo missing: ignored) */
void chain_app_servo(uint8_t servo, int16_t cdeg);

/** the gait clock: ms since START (START reaches every module at the same
 * tick, so every module's clock is the same) */
void chain_app_clock_start(void);
/** ms on the gait clock since chain_app_clock_start() */
uint32_t chain_app_clock_ms(void);
/** make the next control step due now (the gait clock goes on) */
void chain_app_step_now(void);

/** Sleep until the next control step (every ca_control_ms) when periodic is
 * non-zero, else up to 60 s; an I2C frame wakes it earlier. Returns 1 when
 * a control step is due. */
uint8_t chain_app_wait(uint8_t periodic);

#endif
