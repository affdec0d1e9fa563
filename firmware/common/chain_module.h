/** @file
 * Module side of discovery (paper 4.4, the baton along the sync lines),
 * shared by every module program. See docs/firmware.md. */
#ifndef CHAIN_MODULE_H
#define CHAIN_MODULE_H

#include <stdint.h>

/** Sleep (hal_wait_event_ms on I2C / Sin edge) until an ENUM_OFFER arrives
 * while Sin is high, then take the offered address, report type_code to the
 * central control and raise Sout. Returns the address. Frames other than
 * ENUM_OFFER received before that are discarded. */
uint8_t chain_module_discover(uint8_t type_code);

#endif
