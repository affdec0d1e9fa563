/* hal-sim: start-up and time. Time passes only in the three waits below; each
 * is exactly one TICK_END / TICK_BEGIN exchange with the physics server. */
#define _POSIX_C_SOURCE 200809L

#include "hal_time.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_sim_link.h"

/* the HAL event bits are the protocol wake bits */
typedef char hs_ev_i2c_check[(HAL_EV_I2C == CS_WAKE_I2C) ? 1 : -1];
typedef char hs_ev_sin_check[(HAL_EV_SIN_EDGE == CS_WAKE_SIN_EDGE) ? 1 : -1];

static const char *need_env(const char *name)
{
    const char *v = getenv(name);
    if (v == NULL || v[0] == '\0')
        hs_die(HS_EXIT_CONFIG, "environment variable %s is not set "
                               "(module programs are started by the chainsim server)",
               name);
    return v;
}

void hal_init(void)
{
    const char *path, *index_s, *type;
    char *end = NULL;
    long index;

    if (hs.fd >= 0)
        return; /* already connected */

    path = need_env("CHAINSIM_SOCKET");
    index_s = need_env("CHAINSIM_MODULE_INDEX");
    type = need_env("CHAINSIM_MODULE_TYPE");

    errno = 0;
    index = strtol(index_s, &end, 10);
    if (errno != 0 || end == index_s || *end != '\0' || index < 0 || index > 65535)
        hs_die(HS_EXIT_CONFIG, "CHAINSIM_MODULE_INDEX=\"%s\" is not an integer in 0..65535",
               index_s);
    if (strlen(type) >= CS_TYPE_NAME_MAX)
        hs_die(HS_EXIT_CONFIG, "CHAINSIM_MODULE_TYPE=\"%s\" is longer than %u characters", type,
               (unsigned)(CS_TYPE_NAME_MAX - 1));

    hs_connect(path);
    hs_handshake((uint16_t)index, type);
    hs_params_check();
}

/* wake time for a wait of us microseconds (at least one tick, so that every
 * wait makes progress and flushes the outputs) */
static uint64_t wake_after(uint32_t us)
{
    return hs.time_us + (us != 0 ? us : hs.tick_us);
}

void hal_tick_wait(void)
{
    hs_require_init("hal_tick_wait");
    (void)hs_exchange(hs.time_us + hs.tick_us, 0);
}

void hal_delay_ms(uint16_t ms)
{
    hs_require_init("hal_delay_ms");
    (void)hs_exchange(wake_after((uint32_t)ms * 1000u), 0);
}

uint8_t hal_wait_event_ms(uint16_t timeout_ms, uint8_t mask)
{
    uint8_t sin_before, reason, happened;

    hs_require_init("hal_wait_event_ms");
    mask &= (uint8_t)(HAL_EV_I2C | HAL_EV_SIN_EDGE);
    if ((mask & HAL_EV_I2C) && hs.rx_count != 0) {
        /* a frame is already waiting: no need to sleep, and no time passes.
         * A loop that waits like this without reading the frame never
         * reaches the server again: say so once, for its hang report. */
        if (++hs.early_returns == HS_EARLY_RETURNS_NOTICE)
            fprintf(stderr, "chainsim hal: %s %lu times in a row without reading "
                            "the frame (hal_i2c_receive): no simulated time passes\n",
                    CS_NOTICE_WAIT_SPINS, (unsigned long)HS_EARLY_RETURNS_NOTICE);
        return HAL_EV_I2C;
    }

    sin_before = hs.sin_level;
    reason = hs_exchange(wake_after((uint32_t)timeout_ms * 1000u), mask);
    happened = (uint8_t)(reason & mask);
    /* also report what the inputs show, whatever bits the server set */
    if ((mask & HAL_EV_I2C) && hs.rx_count != 0)
        happened |= HAL_EV_I2C;
    if ((mask & HAL_EV_SIN_EDGE) && hs.sin_level != sin_before)
        happened |= HAL_EV_SIN_EDGE;
    return happened;
}

uint32_t hal_millis(void)
{
    return (uint32_t)(hs.time_us / 1000u);
}
