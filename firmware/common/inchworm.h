/** @file
 * The inchworm gait's schedule (gait 8), shared by the support and the
 * extension modules: every module computes its own state from the shared
 * gait clock (ms since START), so no frames pass while it runs.
 *
 * The cycle has n steps of step_ms, one per support, head first. Step i:
 *   first quarter   support i opens its grip (releases)
 *   middle half     extension i-1 retracts (pulls support i forward) and
 *                   extension i extends (pushes support i forward)
 *   last quarter    support i grips again
 * Every other support grips all the time. Supports are counted 0..n-1 and
 * extensions 0..n-2 head first; extension j lies between supports j and j+1.
 * With S E S: step 0 the head support moves forward on the extending
 * extension, step 1 the tail support is pulled after it. */
#ifndef INCHWORM_H
#define INCHWORM_H

#include <stdint.h>

/** this module's part in the schedule, from SET_GAIT (gait 8) */
typedef struct {
    uint16_t step_ms; /**< >= 40 */
    uint8_t index;    /**< the module's number among its type, head first */
    uint8_t n_sup;    /**< supports in the chain, >= 1 */
} iw_schedule;

/** read step_ms, index and n_sup of a SET_GAIT frame, clamped */
void iw_read_schedule(const uint8_t *frame, iw_schedule *s);

/** 1 when support i grips at gait time t_ms */
uint8_t iw_support_grips(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t i);
/** 1 when extension j is extended at gait time t_ms */
uint8_t iw_extension_extended(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t j);

#endif
