/* hal-pic: digital inputs (touch sensors, external pull-ups).
 *   pin 0 = RB6, 1 = RB7, 2 = RC5, 3 = RC2; pins 4..15 read 0. */
#include "hal_gpio.h"

#include "hal_pic.h"

void hp_gpio_init(void)
{
    TRISB |= 0xC0u; /* RB6, RB7 inputs */
    TRISCbits.TRISC2 = 1;
    /* RC5 is input-only while USB is off */
}

uint8_t hal_gpio_read(uint8_t pin)
{
    switch (pin) {
    case 0: return PORTBbits.RB6;
    case 1: return PORTBbits.RB7;
    case 2: return PORTCbits.RC5;
    case 3: return PORTCbits.RC2;
    default: return 0;
    }
}
