/* A module program that misbehaves on purpose, for the fault tests. It sleeps
 * in 10 ms steps like a quiet module until parameter at_ms, then, by mode:
 * 1 hangs in a loop that never calls a HAL wait, 2 crashes with SIGSEGV,
 * 3 exits with code 5, 4 logs a line and crashes with SIGSEGV before any wait,
 * 5 logs a line and exits with code 6 before any wait, 6 waits for I2C frames
 * without ever reading them (the wait returns at once: a busy loop), 7 forks a
 * child that sleeps an hour and goes on quietly, 8 starts a grandchild that
 * leaves the process group (setsid) and sleeps an hour, and goes on quietly.
 * The children write their pid to the file named by CHAINSIM_TEST_PID_FILE. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "hal.h"

const hal_param_decl hal_param_table[] = {
    HAL_PARAM("mode", HAL_PARAM_U8, 0, 8, 0,
              "0 quiet, 1 hang, 2 SIGSEGV, 3 exit 5, 4 log + crash, 5 log + exit 6, 6 spin, 7 fork, 8 setsid grandchild"),
    HAL_PARAM("at_ms", HAL_PARAM_U32, 0, 0x7FFFFFFFL, 100, "when to misbehave, simulated ms"),
    HAL_PARAM_END
};

/* a real invalid write, not raise(): the backtrace must show this function */
#if defined(__GNUC__)
__attribute__((noinline))
#endif
void crash(void);
void crash(void) {
    volatile int *volatile nowhere = NULL;
    *nowhere = 1;
}

/* a process that outlives its parent if nobody ends it: its pid to the file */
static void sleeper(void) {
    const char *file = getenv("CHAINSIM_TEST_PID_FILE");
    if (file) {
        FILE *f = fopen(file, "a");
        if (f) {
            fprintf(f, "%d\n", (int)getpid());
            fclose(f);
        }
    }
    sleep(3600);
    _exit(0);
}

int main(void) {
    hal_init();
    const int32_t mode = hal_param("mode");
    const uint32_t at_ms = (uint32_t)hal_param("at_ms");
    while (hal_millis() < at_ms) hal_delay_ms(10);
    hal_log_int("misbehaving now, mode ", mode);
    if (mode == 4) {
        hal_log("last words before the crash");
        crash();
    }
    if (mode == 5) {
        hal_log("last words before exit");
        exit(6);
    }
    if (mode == 6)
        for (;;) (void)hal_wait_event_ms(100, HAL_EV_I2C);
    if (mode == 7 && fork() == 0) sleeper();
    if (mode == 8 && fork() == 0) {
        setsid();
        if (fork() == 0) sleeper();
        _exit(0);
    }
    hal_tick_wait(); /* the log line reaches the server */
    if (mode == 1) {
        volatile unsigned long spin = 0;
        for (;;) ++spin;
    }
    if (mode == 2) raise(SIGSEGV);
    if (mode == 3) exit(5);
    for (;;) hal_delay_ms(100);
}
