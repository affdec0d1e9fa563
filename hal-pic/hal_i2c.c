/* hal-pic: I2C on the MSSP (RB0 = SDA, RB1 = SCL, 100 kHz, external pull-ups).
 *
 * Receiving: the MSSP is a 7-bit slave with start/stop interrupts (SSPM 1110),
 * general call enabled (GCEN) and clock stretching (SEN), at the address of
 * hal_i2c_set_address (0 = general calls only). The low-priority interrupt
 * collects a frame's bytes and, at its stop (or a repeated start), commits
 * it to a byte ring of HAL_PIC_I2C_RX_RING bytes as len, to_addr7, data.
 * A frame that does not fit, or longer than HAL_I2C_DATA_MAX, is dropped.
 *
 * Sending: hal_i2c_send queues the frame (HAL_PIC_I2C_TX_BUF bytes); the next
 * wait sends the queue as bus master, blocking: wait for the bus to be idle,
 * switch the MSSP to master mode (SSPADD = 49: Fosc / (4 * 50) = 100 kHz),
 * start, address + write, data, stop, then back to slave mode. Lost
 * arbitration (BCLIF) retries; a NACK drops the frame. While sending, the
 * module does not receive (a frame addressed to it then is lost). */
#include "hal_i2c.h"

#include "hal_pic.h"
#include "hal_time.h"

#define RX_MASK ((uint8_t)(HAL_PIC_I2C_RX_RING - 1u))
#define I2C_BRG_100K 49u
#define SEND_ATTEMPTS 3u
#define BUS_IDLE_WAIT_MS 10u

static uint8_t my_addr;

/* receive ring: written by the interrupt between rx_head and rx_w, committed
 * by moving rx_head; read by hal_i2c_receive from rx_tail */
static uint8_t rx_ring[HAL_PIC_I2C_RX_RING];
static volatile uint8_t rx_head;
static volatile uint8_t rx_tail;
static uint8_t rx_w;      /* next byte of the frame being received */
static uint8_t rx_len;    /* its data length */
static uint8_t rx_to;     /* its address (own or 0) */
static uint8_t rx_room;   /* ring bytes free when it began */
static uint8_t rx_active; /* 1: a frame to us is being received */
static uint8_t rx_drop;   /* 1: it does not fit */

/* transmit queue: addr7, len, data... */
static uint8_t tx_buf[HAL_PIC_I2C_TX_BUF];
static uint8_t tx_used;

static void slave_mode(void)
{
    SSPCON1 = 0;
    SSPADD = (uint8_t)(my_addr << 1);
    SSPSTAT = 0x80;  /* SMP: slew-rate control off (100 kHz) */
    SSPCON2 = 0x81;  /* GCEN | SEN (clock stretching) */
    SSPCON1 = 0x3E;  /* SSPEN | CKP | 7-bit slave with start/stop interrupts */
    PIR2bits.BCLIF = 0;
    PIR1bits.SSPIF = 0;
    PIE1bits.SSPIE = 1;
}

void hp_i2c_init(void)
{
    TRISB |= 0x03; /* RB0, RB1 inputs: the MSSP drives them open-drain */
    my_addr = 0;
    rx_head = rx_tail = 0;
    rx_active = 0;
    tx_used = 0;
    IPR1bits.SSPIP = 0; /* low priority */
    slave_mode();
}

static void commit_frame(void)
{
    if (rx_active) {
        if (!rx_drop && rx_len != 0) {
            rx_ring[rx_head] = rx_len;
            rx_ring[(uint8_t)(rx_head + 1u) & RX_MASK] = rx_to;
            rx_head = rx_w;
        }
        rx_active = 0;
    }
}

/* called by the low-priority interrupt when SSPIF is set and SSPIE on (slave mode only) */
void hp_i2c_isr(void)
{
    uint8_t st, b;

    PIR1bits.SSPIF = 0;
    if (SSPCON1bits.SSPOV) {
        b = SSPBUF;
        SSPCON1bits.SSPOV = 0;
        rx_drop = 1;
    }
    st = SSPSTAT;
    if (st & 0x01u) { /* BF: a byte arrived */
        b = SSPBUF;
        if (!(st & 0x20u)) { /* D_A = 0: address byte */
            commit_frame(); /* a repeated start ends the previous frame */
            if (st & 0x04u) {
                SSPBUF = 0xFF; /* a read: the chain protocol has none */
            } else {
                rx_active = 1;
                rx_drop = 0;
                rx_len = 0;
                rx_to = (uint8_t)(b >> 1);
                rx_room = (uint8_t)(RX_MASK - (uint8_t)((uint8_t)(rx_head - rx_tail) & RX_MASK));
                rx_w = (uint8_t)(rx_head + 2u) & RX_MASK;
            }
        } else if (rx_active && !rx_drop) {
            if (rx_len >= HAL_I2C_DATA_MAX || (uint8_t)(rx_len + 2u) >= rx_room) {
                rx_drop = 1;
            } else {
                rx_ring[rx_w] = b;
                rx_w = (uint8_t)(rx_w + 1u) & RX_MASK;
                rx_len++;
            }
        }
    } else if ((st & 0x24u) == 0x24u) {
        SSPBUF = 0xFF; /* a read continues */
    }
    if (st & 0x10u) /* P: stop */
        commit_frame();
    SSPCON1bits.CKP = 1; /* release the clock */
}

uint8_t hp_i2c_frame_waiting(void)
{
    return rx_head != rx_tail;
}

hal_status hal_i2c_set_address(uint8_t addr7)
{
    if (addr7 > 127u)
        return HAL_ERR_ARG;
    my_addr = addr7;
    SSPADD = (uint8_t)(addr7 << 1);
    return HAL_OK;
}

hal_status hal_i2c_send(uint8_t addr7, const uint8_t *data, uint8_t len)
{
    uint8_t i;
    if (addr7 > 127u || data == 0 || len == 0 || len > HAL_I2C_DATA_MAX)
        return HAL_ERR_ARG;
    if ((uint8_t)(len + 2u) > (uint8_t)(HAL_PIC_I2C_TX_BUF - tx_used))
        return HAL_ERR_FULL;
    tx_buf[tx_used++] = addr7;
    tx_buf[tx_used++] = len;
    for (i = 0; i < len; i++)
        tx_buf[tx_used++] = data[i];
    return HAL_OK;
}

hal_status hal_i2c_receive(uint8_t *buf, uint8_t cap, uint8_t *len, uint8_t *to_addr7)
{
    uint8_t t = rx_tail;
    uint8_t n, flen, i;

    if (t == rx_head)
        return HAL_EMPTY;
    flen = rx_ring[t];
    if (to_addr7 != 0)
        *to_addr7 = rx_ring[(uint8_t)(t + 1u) & RX_MASK];
    n = flen < cap ? flen : cap; /* a frame longer than cap is truncated */
    if (buf == 0)
        n = 0;
    t = (uint8_t)(t + 2u) & RX_MASK;
    for (i = 0; i < n; i++)
        buf[i] = rx_ring[(uint8_t)(t + i) & RX_MASK];
    if (len != 0)
        *len = n;
    rx_tail = (uint8_t)(t + flen) & RX_MASK;
    return HAL_OK;
}

/* ---- master send ---------------------------------------------------------- */

/* wait for the MSSP's step to finish: 1 = done, 0 = collision or timeout */
static uint8_t wait_step(void)
{
    uint16_t n = 0;
    while (!PIR1bits.SSPIF) {
        if (PIR2bits.BCLIF || ++n == 0x4000u)
            return 0;
    }
    PIR1bits.SSPIF = 0;
    return !PIR2bits.BCLIF;
}

/* 1 = the bus is idle (stop seen last, or nothing since the MSSP was enabled)
 * and no frame to us is being received */
static uint8_t bus_idle(void)
{
    return (!SSPSTATbits.S || SSPSTATbits.P) && !rx_active;
}

/* send one frame as master: 1 = sent (or NACKed: not worth repeating),
 * 0 = lost arbitration / bus error: try again */
static uint8_t master_send(const uint8_t *f)
{
    uint8_t i, len = f[1], ok = 1;
    uint32_t t0 = hal_millis();

    while (!bus_idle()) {
        if ((uint32_t)(hal_millis() - t0) >= BUS_IDLE_WAIT_MS)
            return 1; /* the bus stays busy: give the frame up */
    }
    PIE1bits.SSPIE = 0;
    SSPCON1 = 0;
    SSPADD = I2C_BRG_100K;
    SSPSTAT = 0x80;
    SSPCON2 = 0;
    SSPCON1 = 0x28; /* SSPEN | master mode, clock = Fosc / (4 * (SSPADD + 1)) */
    PIR1bits.SSPIF = 0;
    PIR2bits.BCLIF = 0;

    SSPCON2bits.SEN = 1; /* start */
    if (!wait_step()) {
        ok = 0;
    } else {
        SSPBUF = (uint8_t)(f[0] << 1); /* address + write */
        if (!wait_step())
            ok = 0;
        for (i = 0; ok && i < len && !SSPCON2bits.ACKSTAT; i++) {
            SSPBUF = f[2 + i];
            if (!wait_step())
                ok = 0;
        }
        if (ok) {
            SSPCON2bits.PEN = 1; /* stop (also after a NACK) */
            if (!wait_step())
                ok = 0;
        }
    }
    slave_mode();
    return ok;
}

void hp_i2c_flush(void)
{
    uint8_t pos = 0, attempt;
    while (pos < tx_used) {
        for (attempt = 0; attempt < SEND_ATTEMPTS; attempt++)
            if (master_send(tx_buf + pos))
                break;
        pos = (uint8_t)(pos + 2u + tx_buf[pos + 1u]);
    }
    tx_used = 0;
}
