/* hal-sim: encoder counters, as of the latest TICK_BEGIN. */
#include "hal_counter.h"

#include "hal_sim_link.h"

int32_t hal_counter_read(uint8_t channel)
{
    if (channel >= hs.n_counters || channel >= CS_COUNTERS_MAX)
        return 0;
    return hs.counter[channel];
}
