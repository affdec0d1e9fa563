/* The central control's waits, log lines and sends: see central_io.h. */
#include "central_io.h"

#include "hal.h"

strbuf cio_sb;
uint8_t cio_rx[HAL_I2C_DATA_MAX];
static uint8_t log_lines; /* logged since the last wait */

void cio_tick_wait(void)
{
    hal_tick_wait();
    log_lines = 0;
}

uint8_t cio_wait_event(uint16_t timeout_ms, uint8_t mask)
{
    uint32_t before = hal_millis();
    uint8_t ev = hal_wait_event_ms(timeout_ms, mask);
    if (hal_millis() != before) /* it did wait (it returns at once when a frame is waiting) */
        log_lines = 0;
    return ev;
}

void cio_new_wait(void)
{
    log_lines = 0;
}

void cio_put(const char *text, int32_t v)
{
    sb_str(&cio_sb, text);
    sb_int(&cio_sb, v);
}

void cio_put_side(uint8_t side)
{
    static const char *const name[4] = {"up", "left", "down", "right"};
    sb_str(&cio_sb, side < 4u ? name[side] : "none");
}

void cio_log_line(const char *line)
{
    if (log_lines >= HAL_LOG_LINES_PER_WAIT)
        cio_tick_wait();
    hal_log(line);
    log_lines++;
}

void cio_log_int(const char *prefix, uint32_t v)
{
    sb_reset(&cio_sb);
    cio_put(prefix, (int32_t)v);
    cio_log_line(cio_sb.buf);
}

void cio_send(uint8_t addr, const uint8_t *data, uint8_t len)
{
    /* the send queue holds only a few frames per wait: wait a tick when full */
    while (hal_i2c_send(addr, data, len) == HAL_ERR_FULL)
        cio_tick_wait();
}

void cio_send_code(uint8_t addr, uint8_t code)
{
    uint8_t b = code;
    cio_send(addr, &b, 1);
}
