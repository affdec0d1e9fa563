/* Log lines: the simulator stores them per module; the board may drop them. */
#ifndef HAL_LOG_H
#define HAL_LOG_H

#include <stdint.h>

/* log one line (truncated to 95 characters); sent at the next wait */
void hal_log(const char *line);

/* log prefix followed by value in decimal, e.g. hal_log_int("addr=", 32) */
void hal_log_int(const char *prefix, int32_t value);

#endif
