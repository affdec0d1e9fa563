/** @file
 * Servomotors: set-point angles and the potentiometer reading. */
#ifndef HAL_SERVO_H
#define HAL_SERVO_H

#include <stdint.h>
#include "hal_status.h"

#define HAL_SERVOS_MAX 4         /**< servos a module can have: 0..3 */
#define HAL_SERVO_CDEG_MAX 18000 /**< setspangle accepts -HAL_SERVO_CDEG_MAX..+HAL_SERVO_CDEG_MAX */

/** set servo's set-point angle in centidegrees (the paper's setspangle);
 * the servo is driven from the next wait on. HAL_ERR_ARG for a servo the
 * module lacks or an angle outside +-HAL_SERVO_CDEG_MAX. A board's servo
 * may turn less (hal-pic: +-9000) and then clamps what it cannot reach. */
hal_status setspangle(uint8_t servo, int16_t angle_cdeg);

/** stop driving servo (no pulses: it goes limp) until the next setspangle */
hal_status hal_servo_release(uint8_t servo);

/** measured output-shaft angle of servo in centidegrees (0 for a missing servo) */
int16_t hal_servo_angle_cdeg(uint8_t servo);

/** number of servos this module has */
uint8_t hal_servo_count(void);

#endif
