/** @file
 * I2C: one shared bus along the chain, 100 kHz, 7-bit addresses.
 * A frame goes to every module; each keeps those for its own address and the
 * general call (address 0), as the MSSP's address match does on the board. */
#ifndef HAL_I2C_H
#define HAL_I2C_H

#include <stdint.h>
#include "hal_status.h"

#define HAL_I2C_GENERAL_CALL 0u /**< the address every module receives */
#define HAL_I2C_DATA_MAX 32u /**< payload bytes of one frame */

/** answer frames sent to addr7 (1..127) from now on; 0 = answer only general calls */
hal_status hal_i2c_set_address(uint8_t addr7);

/** queue a frame of len (1..HAL_I2C_DATA_MAX) bytes to addr7; it is put on the
 * bus at the next wait. HAL_ERR_FULL when the send queue is full, as a
 * board's would be: 8 frames queued this tick, or 512 bytes (address byte
 * and data of each frame) of this module's own still waiting on the 100 kHz
 * bus (in the simulator; the PIC board's queue holds 40, hal-pic/README.md).
 * Try again after a wait. */
hal_status hal_i2c_send(uint8_t addr7, const uint8_t *data, uint8_t len);

/** take the oldest received frame: copies up to cap bytes into buf, its length
 * into *len and the address it was sent to (own or 0) into *to_addr7.
 * HAL_OK, or HAL_EMPTY when no frame is waiting */
hal_status hal_i2c_receive(uint8_t *buf, uint8_t cap, uint8_t *len, uint8_t *to_addr7);

#endif
