/* Central side of discovery: see discovery.h. */
#include "discovery.h"

#include "central_io.h"
#include "hal.h"

#define ENUM_REPLY_TIMEOUT_MS 200u
#define ENUM_REOFFER_MS 20u /* a module ignores an offer that came as its Sin rose: offer again */
#define SYNC_SETTLE_MS 2u /* let Sout reach module 0's Sin before the first offer */

uint8_t chain_n_modules;
uint8_t chain_module_type[CHAIN_MAX_MODULES];

/* wait up to ENUM_REPLY_TIMEOUT_MS for ENUM_REPLY from addr, offering again
 * every ENUM_REOFFER_MS; 1 = got it (type stored), 0 = no reply. *closed
 * is set when our Sin is high. */
static uint8_t await_enum_reply(const uint8_t *offer, uint8_t *closed)
{
    uint8_t addr = offer[1];
    uint32_t deadline = hal_millis() + ENUM_REPLY_TIMEOUT_MS;
    uint32_t reoffer = hal_millis() + ENUM_REOFFER_MS;
    uint8_t len, to;

    for (;;) {
        uint32_t now, until;
        while (hal_i2c_receive(cio_rx, sizeof cio_rx, &len, &to) == HAL_OK) {
            if (len == CC_ENUM_REPLY_LEN && cio_rx[0] == CC_ENUM_REPLY && cio_rx[1] == addr) {
                chain_module_type[chain_n_modules] = cio_rx[2];
                return 1;
            }
        }
        *closed = hal_sync_read_sin();
        if (*closed)
            return 0; /* the ring closed: nobody is left to take addr */
        now = hal_millis();
        if ((int32_t)(now - deadline) >= 0)
            return 0;
        if ((int32_t)(now - reoffer) >= 0) {
            cio_send(HAL_I2C_GENERAL_CALL, offer, CC_ENUM_OFFER_LEN);
            reoffer = now + ENUM_REOFFER_MS;
        }
        until = (int32_t)(reoffer - deadline) < 0 ? reoffer : deadline;
        (void)cio_wait_event((uint16_t)(until - now), HAL_EV_I2C | HAL_EV_SIN_EDGE);
    }
}

static void log_no_reply(uint8_t addr)
{
    sb_reset(&cio_sb);
    cio_put("discovery: no reply at position ", chain_n_modules);
    sb_str(&cio_sb, " (address ");
    sb_hex8(&cio_sb, addr);
    cio_put(") within 200 ms; continuing with ", chain_n_modules);
    sb_str(&cio_sb, " modules");
    cio_log_line(cio_sb.buf);
}

static void log_chain(void)
{
    uint8_t i;
    sb_reset(&cio_sb);
    sb_str(&cio_sb, "chain: ");
    for (i = 0; i < chain_n_modules; i++)
        sb_char(&cio_sb, cc_type_letter(chain_module_type[i]));
    if (chain_n_modules != 0)
        sb_char(&cio_sb, ' ');
    cio_put("(", chain_n_modules);
    sb_str(&cio_sb, " modules)");
    cio_log_line(cio_sb.buf);
}

void discovery_run(void)
{
    uint8_t offer[CC_ENUM_OFFER_LEN];
    uint8_t addr, closed = 0;

    chain_n_modules = 0;
    hal_sync_write_sout(1);
    hal_delay_ms(SYNC_SETTLE_MS);
    cio_new_wait();
    for (;;) {
        if (hal_sync_read_sin())
            break; /* the baton came back: chain complete */
        if (chain_n_modules >= CHAIN_MAX_MODULES) {
            cio_log_line("discovery: too many modules, stopping");
            break;
        }
        addr = (uint8_t)(CHAIN_FIRST_MODULE_ADDR + chain_n_modules);
        offer[0] = CC_ENUM_OFFER;
        offer[1] = addr;
        cio_send(HAL_I2C_GENERAL_CALL, offer, CC_ENUM_OFFER_LEN);
        if (await_enum_reply(offer, &closed)) {
            chain_n_modules++;
            continue;
        }
        if (!closed)
            log_no_reply(addr);
        break;
    }
    log_chain();
}

void chain_send_to_type(uint8_t type, const uint8_t *data, uint8_t len)
{
    uint8_t i;
    for (i = 0; i < chain_n_modules; i++)
        if (chain_module_type[i] == type)
            cio_send((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), data, len);
}
