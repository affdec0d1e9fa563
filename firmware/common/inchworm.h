/** @file
 * The inchworm gaits' schedules (gait 8 and gait 13), shared by the support
 * and the extension modules: every module computes its own state from the
 * shared gait clock (ms since START), so no frames pass while it runs.
 *
 * Gait 8, the travelling wave:
 * The cycle has n steps of step_ms, one per support, head first. Step i:
 *   first quarter   support i opens its grip (releases)
 *   middle half     extension i-1 retracts (pulls support i forward) and
 *                   extension i extends (pushes support i forward)
 *   last quarter    support i grips again
 * Every other support grips all the time. Supports are counted 0..n-1 and
 * extensions 0..n-2 head first; extension j lies between supports j and j+1.
 * With S E S: step 0 the head support moves forward on the extending
 * extension, step 1 the tail support is pulled after it.
 *
 * Gait 13, all the extensions together (paper 6.5: "total extension equals
 * the extension produced by one extension module times the number of
 * extension modules"). The cycle has 2 steps of step_ms, whatever n:
 *   step 0 (push)  the tail support grips; every other support releases in
 *                  the first quarter; every extension extends in the middle
 *                  half (the head goes n-1 strokes forward); the head
 *                  support grips in the last quarter
 *   step 1 (pull)  the head support grips; every other support releases in
 *                  the first quarter; every extension retracts in the middle
 *                  half (the tail is pulled n-1 strokes forward); the tail
 *                  support grips in the last quarter
 * The supports between head and tail never grip while it runs: every one of
 * them moves in both steps. With S E S it is gait 8 exactly. */
#ifndef INCHWORM_H
#define INCHWORM_H

#include <stdint.h>

/** this module's part in the schedule, from SET_GAIT (gait 8) */
typedef struct {
    uint16_t step_ms; /**< >= 40 */
    uint8_t index;    /**< the module's number among its type, head first */
    uint8_t n_sup;    /**< supports in the chain, >= 1 */
    uint8_t gait;     /**< GAIT_INCHWORM or GAIT_INCHWORM_ALL (any other: GAIT_INCHWORM) */
} iw_schedule;

/** read step_ms, index, n_sup and the gait code of a SET_GAIT frame, clamped */
void iw_read_schedule(const uint8_t *frame, iw_schedule *s);

/** 1 when support i grips at gait time t_ms */
uint8_t iw_support_grips(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t i);
/** 1 when extension j is extended at gait time t_ms */
uint8_t iw_extension_extended(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t j);

/** gait 13: 1 when support i of n grips at gait time t_ms */
uint8_t iw_all_support_grips(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t i);
/** gait 13: 1 when the extensions (all of them alike) are extended at gait time t_ms */
uint8_t iw_all_extended(uint32_t t_ms, uint16_t step_ms);

/** under its schedule's gait (8 or 13): 1 when support s->index grips at
 * gait time t_ms */
uint8_t iw_grips(const iw_schedule *s, uint32_t t_ms);
/** under its schedule's gait (8 or 13): 1 when extension s->index is
 * extended at gait time t_ms */
uint8_t iw_extended(const iw_schedule *s, uint32_t t_ms);

#endif
