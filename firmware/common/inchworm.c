/* The inchworm schedules (gaits 8 and 13): see inchworm.h. */
#include "inchworm.h"

#include "chain_commands.h"

void iw_read_schedule(const uint8_t *frame, iw_schedule *s)
{
    int16_t g = cc_get_i16(frame + CC_GAIT_OFF_STEP);
    s->step_ms = (uint16_t)(g < 40 ? 40 : g);
    g = cc_get_i16(frame + CC_GAIT_OFF_INDEX);
    s->index = (uint8_t)(g < 0 ? 0 : (g > 255 ? 255 : g));
    s->n_sup = frame[CC_GAIT_OFF_NSUP] == 0 ? 1u : frame[CC_GAIT_OFF_NSUP];
    s->gait = frame[CC_GAIT_OFF_GAIT] == GAIT_INCHWORM_ALL ? GAIT_INCHWORM_ALL : GAIT_INCHWORM;
}

/* step s (0..n-1) and quarter q (0..3) of the step at time t */
static void iw_phase(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t *s, uint8_t *q)
{
    uint32_t tau;
    if (step_ms == 0)
        step_ms = 1;
    if (n == 0)
        n = 1;
    *s = (uint8_t)((t_ms / step_ms) % n);
    tau = t_ms % step_ms;
    *q = (uint8_t)((tau * 4u) / step_ms);
}

uint8_t iw_support_grips(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t i)
{
    uint8_t s, q;
    iw_phase(t_ms, step_ms, n, &s, &q);
    return !(s == i && q < 3u);
}

uint8_t iw_extension_extended(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t j)
{
    uint8_t s, q;
    iw_phase(t_ms, step_ms, n, &s, &q);
    if (s == j)
        return q >= 1u;
    if ((uint8_t)(j + 1u) == s)
        return q == 0u;
    return 0;
}

/* gait 13: the anchor of step s (0 push: the tail, n - 1; 1 pull: the head, 0)
 * grips through the step; the anchor of the next step grips in the step's
 * last quarter; every other support is released. */
uint8_t iw_all_support_grips(uint32_t t_ms, uint16_t step_ms, uint8_t n, uint8_t i)
{
    uint8_t s, q, tail;
    if (n <= 1)
        return 1; /* a lone support has nothing to move: it holds */
    iw_phase(t_ms, step_ms, 2, &s, &q);
    tail = (uint8_t)(n - 1u);
    if (i == (s == 0 ? tail : 0))
        return 1;
    if (i == (s == 0 ? 0 : tail))
        return q == 3u;
    return 0;
}

/* gait 13: out from the push's second quarter to the pull's second quarter */
uint8_t iw_all_extended(uint32_t t_ms, uint16_t step_ms)
{
    uint8_t s, q;
    iw_phase(t_ms, step_ms, 2, &s, &q);
    return s == 0 ? q >= 1u : q == 0u;
}

uint8_t iw_grips(const iw_schedule *s, uint32_t t_ms)
{
    if (s->gait == GAIT_INCHWORM_ALL)
        return iw_all_support_grips(t_ms, s->step_ms, s->n_sup, s->index);
    return iw_support_grips(t_ms, s->step_ms, s->n_sup, s->index);
}

uint8_t iw_extended(const iw_schedule *s, uint32_t t_ms)
{
    if (s->gait == GAIT_INCHWORM_ALL)
        return iw_all_extended(t_ms, s->step_ms);
    return iw_extension_extended(t_ms, s->step_ms, s->n_sup, s->index);
}
