/* A millisecond clock kept in an unsigned int: 32 bits on a PC, 16 on the
 * PIC18, where it wraps after 65.535 s. Logs it, in whole seconds, every 5 s
 * of the 32-bit clock. */
#include "hal.h"

const hal_param_decl hal_param_table[] = {
    HAL_PARAM_END
};

int main(void)
{
    uint32_t next = 0;
    hal_init();
    for (;;) {
        unsigned int t_ms = hal_millis();
        hal_log_int("clock: t_s = ", (int32_t)((t_ms + 500u) / 1000u));
        next += 5000u;
        hal_delay_ms((uint16_t)(next - hal_millis()));
    }
}
