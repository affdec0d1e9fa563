/* hal-sim: I2C. Frames to send are queued and put in the next TICK_END (at
 * most CS_I2C_FRAMES_MAX per wait); frames the server delivers in TICK_BEGIN
 * go to a ring of HS_RX_RING (the oldest is dropped when it is full). The
 * server routes by the address this module reports, as the MSSP's address
 * match would. */
#include "hal_i2c.h"

#include <string.h>

#include "hal_sim_link.h"

typedef char hs_i2c_max_check[(HAL_I2C_DATA_MAX == CS_I2C_DATA_MAX) ? 1 : -1];

hal_status hal_i2c_set_address(uint8_t addr7)
{
    if (addr7 > 127u)
        return HAL_ERR_ARG;
    hs.i2c_address = addr7;
    return HAL_OK;
}

hal_status hal_i2c_send(uint8_t addr7, const uint8_t *data, uint8_t len)
{
    cs_i2c_frame *f;
    if (addr7 > 127u || data == NULL || len == 0 || len > HAL_I2C_DATA_MAX)
        return HAL_ERR_ARG;
    if (hs.n_i2c_tx >= CS_I2C_FRAMES_MAX)
        return HAL_ERR_FULL;
    {
        /* the send queue, as the board's: what is still on the bus, what this
         * tick queued, and this frame (its address byte and data) */
        unsigned queued = hs.i2c_tx_queued;
        uint8_t i;
        for (i = 0; i < hs.n_i2c_tx; i++)
            queued += hs.i2c_tx[i].len + 1u;
        if (queued + len + 1u > CS_I2C_TX_QUEUE_MAX)
            return HAL_ERR_FULL;
    }
    f = &hs.i2c_tx[hs.n_i2c_tx++];
    f->addr = addr7;
    f->len = len;
    memcpy(f->data, data, len);
    return HAL_OK;
}

hal_status hal_i2c_receive(uint8_t *buf, uint8_t cap, uint8_t *len, uint8_t *to_addr7)
{
    const cs_i2c_frame *f;
    uint8_t n;
    if (hs.rx_count == 0)
        return HAL_EMPTY;
    f = &hs.rx[hs.rx_head];
    n = f->len < cap ? f->len : cap; /* a frame longer than cap is truncated */
    if (buf != NULL && n != 0)
        memcpy(buf, f->data, n);
    if (len != NULL)
        *len = buf != NULL ? n : 0;
    if (to_addr7 != NULL)
        *to_addr7 = f->addr;
    hs.rx_head = (uint8_t)((hs.rx_head + 1u) % HS_RX_RING);
    hs.rx_count--;
    return HAL_OK;
}
