/* hal-pic: the synchronism lines. Sin = RC4 (a digital input while USB is
 * off), sampled by the 1 ms tick; Sout = RC1, driven from the next wait on. */
#include "hal_sync.h"

#include "hal_pic.h"

static uint8_t sout_pending;

void hp_sync_init(void)
{
    LATCbits.LATC1 = 0;
    TRISCbits.TRISC1 = 0; /* Sout output, low */
    sout_pending = 0;
    /* RC4 is input-only (UCFG.UTRDIS set by hal_init) */
}

void hp_sync_flush(void)
{
    LATCbits.LATC1 = sout_pending;
}

uint8_t hal_sync_read_sin(void)
{
    return hp_sin_level;
}

void hal_sync_write_sout(uint8_t level)
{
    sout_pending = level != 0 ? 1u : 0u;
}
