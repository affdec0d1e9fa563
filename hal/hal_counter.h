/** @file
 * Encoder counters (traveller wheels). */
#ifndef HAL_COUNTER_H
#define HAL_COUNTER_H

#include <stdint.h>

/** counts accumulated by counter channel since start (0 for a missing one) */
int32_t hal_counter_read(uint8_t channel);

#endif
