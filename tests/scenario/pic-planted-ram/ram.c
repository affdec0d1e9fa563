/* A 300-byte local array: fine on a PC; on the PIC18 SDCC keeps locals in
 * static RAM, and one object cannot span the 256-byte banks. */
#include "hal.h"

const hal_param_decl hal_param_table[] = {
    HAL_PARAM_END
};

static uint8_t sum(const uint8_t *b, uint16_t n)
{
    uint8_t s = 0;
    while (n-- > 0)
        s = (uint8_t)(s + *b++);
    return s;
}

int main(void)
{
    uint8_t samples[300];
    uint16_t i;
    hal_init();
    for (i = 0; i < sizeof samples; i++)
        samples[i] = (uint8_t)hal_adc_read(0);
    hal_log_int("sum: ", sum(samples, sizeof samples));
    for (;;)
        hal_delay_ms(1000);
}
