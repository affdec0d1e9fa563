/* Central side of discovery (paper 4.4, the baton along the sync lines):
 * raise Sout, offer addresses 0x20, 0x21, ... by general call; the module
 * holding the baton (Sin high, no address) takes it, answers with its type
 * and raises its Sout. Done when the central's Sin (driven by the last
 * module's Sout) goes high. See docs/firmware.md, "Discovery". */
#ifndef DISCOVERY_H
#define DISCOVERY_H

#include <stdint.h>

#include "chain_commands.h"

/* the chain found: module k has address CHAIN_FIRST_MODULE_ADDR + k */
extern uint8_t chain_n_modules;
extern uint8_t chain_module_type[CHAIN_MAX_MODULES]; /* MT_* */

/* run discovery and log "chain: RRRR (4 modules)" */
void discovery_run(void);

/* send a frame to every module of the given type, in chain order */
void chain_send_to_type(uint8_t type, const uint8_t *data, uint8_t len);

#endif
