/* The inchworm schedule: see inchworm.h. */
#include "inchworm.h"

#include "chain_commands.h"

void iw_read_schedule(const uint8_t *frame, iw_schedule *s)
{
    int16_t g = cc_get_i16(frame + CC_GAIT_OFF_STEP);
    s->step_ms = (uint16_t)(g < 40 ? 40 : g);
    g = cc_get_i16(frame + CC_GAIT_OFF_INDEX);
    s->index = (uint8_t)(g < 0 ? 0 : (g > 255 ? 255 : g));
    s->n_sup = frame[CC_GAIT_OFF_NSUP] == 0 ? 1u : frame[CC_GAIT_OFF_NSUP];
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
