/* A module program that logs lines made to defeat a backtracking regular
 * expression engine, for the tests of `chainsim test`'s log patterns: first
 * one line of 80 'a', then every 10 ms a line of 80 'a' and a 'b', until the
 * run ends. It takes no part in discovery (its chain entry says
 * may_stay_silent). A pattern such as /^(a+)+$/ tried by backtracking on a
 * line of the second kind takes 2^80 steps; RE2 takes one pass. */
#include <string.h>

#include "hal.h"

#define RUN 80

const hal_param_decl hal_param_table[] = {HAL_PARAM_END}; /* no parameters */

int main(void) {
    char line[RUN + 2];
    hal_init();
    memset(line, 'a', RUN);
    line[RUN] = '\0';
    hal_log(line);
    line[RUN] = 'b';
    line[RUN + 1] = '\0';
    for (;;) {
        hal_delay_ms(10);
        hal_log(line);
    }
}
