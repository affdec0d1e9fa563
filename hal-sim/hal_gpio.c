/* hal-sim: digital inputs, as of the latest TICK_BEGIN. */
#include "hal_gpio.h"

#include "hal_sim_link.h"

uint8_t hal_gpio_read(uint8_t pin)
{
    if (pin > 15u)
        return 0;
    return (uint8_t)((hs.digital_in >> pin) & 1u);
}
