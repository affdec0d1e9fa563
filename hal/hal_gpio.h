/** @file
 * Digital inputs (touch sensors). */
#ifndef HAL_GPIO_H
#define HAL_GPIO_H

#include <stdint.h>

#define HAL_GPIO_PINS 16u /**< digital inputs 0..15; a pin the board lacks reads 0 */

/** level of digital input pin (0..HAL_GPIO_PINS - 1), 0 or 1 */
uint8_t hal_gpio_read(uint8_t pin);

#endif
