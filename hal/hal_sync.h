/** @file
 * The two synchronism lines: Sin from the previous module in the chain,
 * Sout to the next (the central control's Sout drives the first module's Sin,
 * the last module's Sout drives the central control's Sin). */
#ifndef HAL_SYNC_H
#define HAL_SYNC_H

#include <stdint.h>

/** level of Sin, 0 or 1, as sampled at the last tick */
uint8_t hal_sync_read_sin(void);

/** drive Sout to level (0 or 1) from the next wait on */
void hal_sync_write_sout(uint8_t level);

#endif
