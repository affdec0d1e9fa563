/* A module program that misbehaves on purpose, for the fault tests. It sleeps
 * in 10 ms steps like a quiet module until parameter at_ms, then, by mode:
 * 1 hangs in a loop that never calls a HAL wait, 2 crashes with SIGSEGV,
 * 3 exits with code 5. */
#include <signal.h>
#include <stdlib.h>

#include "hal.h"

int main(void) {
    hal_init();
    const int32_t mode = hal_param("mode", 0);
    const uint32_t at_ms = (uint32_t)hal_param("at_ms", 100);
    while (hal_millis() < at_ms) hal_delay_ms(10);
    hal_log_int("misbehaving now, mode ", mode);
    hal_tick_wait(); /* the log line reaches the server */
    if (mode == 1) {
        volatile unsigned long spin = 0;
        for (;;) ++spin;
    }
    if (mode == 2) raise(SIGSEGV);
    if (mode == 3) exit(5);
    for (;;) hal_delay_ms(100);
}
