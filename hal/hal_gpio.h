/* Digital inputs (touch sensors). */
#ifndef HAL_GPIO_H
#define HAL_GPIO_H

#include <stdint.h>

/* level of digital input pin (0..15), 0 or 1 */
uint8_t hal_gpio_read(uint8_t pin);

#endif
