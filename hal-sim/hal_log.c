/* hal-sim: log lines, sent in the next TICK_END (at most CS_LOG_LINES_MAX per
 * wait; the rest are counted and reported as "log: N lines dropped"). */
#include "hal_log.h"

#include <string.h>

#include "hal_sim_link.h"

/* the protocol's line buffer holds a HAL line and its NUL; its per-tick
 * limit is the HAL's guaranteed lines per wait */
typedef char hs_log_line_check[(HAL_LOG_LINE_MAX + 1u == CS_LOG_LINE_MAX) ? 1 : -1];
typedef char hs_log_lines_check[(HAL_LOG_LINES_PER_WAIT == CS_LOG_LINES_MAX) ? 1 : -1];

void hal_log(const char *line)
{
    hs_log_line(line != NULL ? line : "");
}

void hal_log_int(const char *prefix, int32_t value)
{
    char line[CS_LOG_LINE_MAX];
    char digits[12];
    size_t n = 0, k = 0;
    uint32_t mag;

    if (prefix != NULL) {
        n = strlen(prefix);
        if (n > HAL_LOG_LINE_MAX - HAL_LOG_INT_CHARS_MAX)
            n = HAL_LOG_LINE_MAX - HAL_LOG_INT_CHARS_MAX; /* keep room for the number */
        memcpy(line, prefix, n);
    }
    if (value < 0) {
        line[n++] = '-';
        mag = (uint32_t)0 - (uint32_t)value;
    } else {
        mag = (uint32_t)value;
    }
    do {
        digits[k++] = (char)('0' + mag % 10u);
        mag /= 10u;
    } while (mag != 0);
    while (k > 0)
        line[n++] = digits[--k];
    line[n] = '\0';
    hs_log_line(line);
}
