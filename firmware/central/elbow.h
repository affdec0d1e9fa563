/* Elbow negotiation (gait 9; paper 6.1-6.2): when the touch module reports
 * a contact, bend the rotation modules toward the turn (SET_GAIT gait 10)
 * while the helicoidal modules push, each for bend_ms, then straighten them. The first rotation module bends at the
 * contact, each one behind it bend_travel_ms per place in the chain later
 * (0: all at once), so that the bend can travel down the chain as it
 * advances. A contact while the steering lasts, or within bend_ms after it
 * ended (the head meeting the outgoing leg's wall), is the same elbow. The
 * turn is away from where the touch module was touched (the head meets the
 * bend's outer wall), or elbow_dir_deg when the scene gives it (>= 0); -2
 * turns the steering off. Pushed head-on (a wall ahead: a split, a tee),
 * the turn is the junction policy's, left or right of up (params.junction).
 * With a junction policy the central control waits JUNCTION_WINDOW_MS after
 * a contact before it turns: a head meeting the wedge between a split's two
 * outlets touches one side first, then both, and all three switches closed
 * at once within the window are a wall ahead. Without one it turns at the
 * contact. A chain without rotation modules never steers. A stall of the
 * helicoidal modules (stall_counts, main.c) is a contact with no direction:
 * it steers toward elbow_dir_deg when given. With bend_limp the rotation
 * modules go limp (gait 12) after bend_ms instead of straightening; with
 * hold_ms the support modules grip the wall (gait 11) from the bend for
 * hold_ms (paper 6.6). See docs/firmware.md, "Elbow negotiation". */
#ifndef ELBOW_H
#define ELBOW_H

#include <stdint.h>

/* after discovery: whether it steers (gait 9, elbow_dir_deg not -2, a
 * rotation module in the chain), and the bend's pitch and yaw from
 * elbow_dir_deg, when given, and bend_cdeg (central_params.h) */
void elbow_setup(void);

/* log "elbow: dir_deg=... pitch_cdeg=... yaw_cdeg=... bend_ms=..." (given)
 * or "elbow: sensed bend_cdeg=... bend_ms=..." (sensed), with
 * " bend_travel_ms=..." when not 0 and " junction=left" (right) with a
 * junction policy; nothing when steering is off, the gait is not 9 or the
 * chain has no rotation module */
void elbow_log(void);

/* a TOUCH contact (or a stall: no direction) at now while gait 9 runs, the obstacle at obstacle_deg and
 * up at up_deg in the touch module's frame (CC_TOUCH_NONE: head-on; gravity
 * along the axis): bend, unless steering is off, the direction is unknown,
 * or this is the elbow already being passed. The log line gives the turn in
 * the touch module's frame and, when the touch module knew where up was, as
 * gravity gives it (0 up, 90 left, 180 down, 270 right), and why: "elbow:
 * bend at ms T toward dir_deg=D world_deg=W (sensed)", "(junction, left)"
 * or "(given)". */
void elbow_contact(uint32_t now, int16_t obstacle_deg, int16_t up_deg);

/* when the steering ended (a contact within bend_ms after it is the same
 * elbow) */
extern uint32_t elbow_bend_end;

/* when elbow_update must run next (valid while it returns 1) */
extern uint32_t elbow_wake;

/* how long a contact is watched before the turn, with a junction policy, ms */
#define JUNCTION_WINDOW_MS 200u

/* bend and straighten (or let go limp) the rotation modules whose time has
 * come, let the support modules go when hold_ms has passed, or turn once a
 * contact's window has passed (head_on: all three switches were closed at
 * once since the last call); forget the steering after STOP, which
 * straightened the modules. Logs "elbow: straight at ms T" ("limp"), "elbow:
 * release at ms T". Returns 1 while the steering or the hold lasts:
 * elbow_update must run again at elbow_wake. */
uint8_t elbow_update(uint32_t now, uint8_t stopped, uint8_t head_on);

#endif
