/* Elbow negotiation (gait 9, parameter elbow_dir_deg >= 0; paper 6.1-6.2):
 * when the touch module reports a contact, bend the rotation modules toward
 * the turn (SET_GAIT gait 10) while the helicoidal modules push, each for
 * bend_ms, then straighten them. The first rotation module bends at the
 * contact, each one behind it bend_travel_ms per place in the chain later
 * (0: all at once), so that the bend can travel down the chain as it
 * advances. A contact while the steering lasts, or within bend_ms after it
 * ended (the head meeting the outgoing leg's wall), is the same elbow. See
 * docs/firmware.md, "Elbow negotiation". */
#ifndef ELBOW_H
#define ELBOW_H

#include <stdint.h>

/* the bend's pitch and yaw from elbow_dir_deg and bend_cdeg (central_params.h) */
void elbow_setup(void);

/* log "elbow: dir_deg=... pitch_cdeg=... yaw_cdeg=... bend_ms=..." (and
 * " bend_travel_ms=..." when not 0) when steering is on */
void elbow_log(void);

/* a TOUCH contact at now while gait 9 runs: bend, unless steering is off or
 * this is the elbow already being passed */
void elbow_contact(uint32_t now);

/* the steering's next change (valid while elbow_update returns 1), or when
 * it ended */
extern uint32_t elbow_bend_end;

/* bend and straighten the rotation modules whose time has come (or forget
 * the steering after STOP, which straightened the modules). Returns 1 while
 * the steering lasts: elbow_update must run again at elbow_bend_end. */
uint8_t elbow_update(uint32_t now, uint8_t stopped);

#endif
