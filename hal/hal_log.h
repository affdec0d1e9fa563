/** @file
 * Log lines: the simulator stores them per module; the board writes them to
 * its UART (hal-pic/README.md). */
#ifndef HAL_LOG_H
#define HAL_LOG_H

#include <stdint.h>

#define HAL_LOG_LINE_MAX 95u      /**< characters of a line (without the NUL); longer ones are cut */
#define HAL_LOG_INT_CHARS_MAX 11u /**< hal_log_int's number: "-2147483648" */
/** lines per wait that always reach the log; the simulator drops the ones
 * beyond (and says so in the last line), the board's UART takes any number */
#define HAL_LOG_LINES_PER_WAIT 4u

/** log one line (truncated to HAL_LOG_LINE_MAX characters); sent at the next wait */
void hal_log(const char *line);

/** log prefix followed by value in decimal, e.g. hal_log_int("addr=", 32);
 * the prefix is cut to HAL_LOG_LINE_MAX - HAL_LOG_INT_CHARS_MAX characters so
 * that the number always fits */
void hal_log_int(const char *prefix, int32_t value);

#endif
