/* hal-sim: digital inputs, as of the latest TICK_BEGIN. */
#include "hal_gpio.h"

#include "hal_sim_link.h"

/* TICK_BEGIN's digital_in has one bit per pin */
typedef char hs_gpio_pins_check[(HAL_GPIO_PINS <= 8u * sizeof hs.digital_in) ? 1 : -1];

uint8_t hal_gpio_read(uint8_t pin)
{
    if (pin >= HAL_GPIO_PINS)
        return 0;
    return (uint8_t)((hs.digital_in >> pin) & 1u);
}
