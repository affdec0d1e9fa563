/* Elbow negotiation (gait 9, parameter elbow_dir_deg >= 0; paper 6.1-6.2):
 * when the touch module reports a contact, bend every rotation module toward
 * the turn (SET_GAIT gait 10) for bend_ms while the helicoidal modules push,
 * then straighten them. A contact while bent, or within bend_ms after
 * straightening (the head meeting the outgoing leg's wall), is the same
 * elbow. See docs/firmware.md, "Elbow negotiation". */
#ifndef ELBOW_H
#define ELBOW_H

#include <stdint.h>

/* the bend's pitch and yaw from elbow_dir_deg and bend_cdeg (central_params.h) */
void elbow_setup(void);

/* log "elbow: dir_deg=... pitch_cdeg=... yaw_cdeg=... bend_ms=..." when
 * steering is on */
void elbow_log(void);

/* a TOUCH contact at now while gait 9 runs: bend, unless steering is off or
 * this is the elbow already being passed */
void elbow_contact(uint32_t now);

/* when the bend held now ends (valid while elbow_update returns 1) */
extern uint32_t elbow_bend_end;

/* straighten when the bend's time is up (or forget it after STOP, which
 * straightened the modules). Returns 1 while a bend is held: elbow_update
 * must run again at elbow_bend_end. */
uint8_t elbow_update(uint32_t now, uint8_t stopped);

#endif
