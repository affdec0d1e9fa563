/* hal-sim: the synchronism lines Sin (input, sampled each tick) and Sout. */
#include "hal_sync.h"

#include "hal_sim_link.h"

uint8_t hal_sync_read_sin(void)
{
    return hs.sin_level;
}

void hal_sync_write_sout(uint8_t level)
{
    hs.sout_level = level != 0 ? 1u : 0u;
}
