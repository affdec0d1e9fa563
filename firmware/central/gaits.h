/* The gait commands: SET_GAIT to the modules a gait moves, addressed so that
 * other module types never see it (gaits 1-7: rotation modules; 8 inchworm
 * and 13 inchworm with every extension at once: supports and extensions,
 * each with its index; 9 helicoidal drive:
 * helicoidal modules; 10 bend, 12 limp: rotation modules; 11 hold:
 * supports). START and STOP go by
 * general call from main.c. Parameters: central_params.h. */
#ifndef GAITS_H
#define GAITS_H

#include <stdint.h>

/* log the gait's parameters ("gait: code=... ", and a second line for
 * gaits 3 and up) */
void gaits_log(void);

/* SET_GAIT of params.gait to every module it moves */
void gaits_send(void);

/* gait 10 to the module at chain index `module` (a rotation module): hold
 * pitch and yaw (cdeg) */
void gaits_send_bend(uint8_t module, int16_t pitch_cdeg, int16_t yaw_cdeg);

/* SET_GAIT gait 11 (hold: grip at grip_cdeg at once) to every support
 * module when hold is non-zero, else gait 0 (arms closed) */
void gaits_send_hold(uint8_t hold);

/* gait 8 (inchworm) or 13 (inchworm, every extension at once) to every
 * support and extension, each with its index */
void gaits_send_inchworm(uint8_t gait);

/* SET_GAIT gait 0 to every module of the type (MT_*): a support closes its
 * arms, an extension retracts */
void gaits_send_none(uint8_t type);

/* gait 12 to the module at chain index `module` (a rotation module): its
 * servos go limp */
void gaits_send_limp(uint8_t module);

#endif
