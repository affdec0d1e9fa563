/* Module side of discovery: see chain_module.h. */
#include "chain_module.h"

#include "chain_commands.h"
#include "hal.h"

#define DISCOVERY_SLEEP_MS 60000u /* just a long sleep; events wake us */

uint8_t chain_module_discover(uint8_t type_code)
{
    uint8_t buf[HAL_I2C_DATA_MAX];
    uint8_t len, to, addr;
    uint8_t reply[CC_ENUM_REPLY_LEN];
    uint8_t sin_before; /* Sin as the wait began in which the frames came */

    hal_sync_write_sout(0);
    hal_i2c_set_address(0);
    sin_before = hal_sync_read_sin();
    for (;;) {
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            if (len != CC_ENUM_OFFER_LEN || buf[0] != CC_ENUM_OFFER ||
                to != HAL_I2C_GENERAL_CALL)
                continue;
            /* An offer is ours only if Sin was high before it came: one that
             * came in the wait in which Sin rose may be the upstream
             * module's, which took it and passed the baton meanwhile (on
             * the board a module answers at its own 1 ms tick, so its
             * downstream neighbour may read that offer after the edge).
             * The central control offers again when nobody answers. */
            if (!sin_before)
                continue;
            addr = buf[1];
            if (addr < CHAIN_FIRST_MODULE_ADDR ||
                addr >= CHAIN_FIRST_MODULE_ADDR + CHAIN_MAX_MODULES)
                continue;
            hal_i2c_set_address(addr);
            reply[0] = CC_ENUM_REPLY;
            reply[1] = addr;
            reply[2] = type_code;
            hal_i2c_send(CHAIN_CENTRAL_ADDR, reply, CC_ENUM_REPLY_LEN);
            hal_sync_write_sout(1); /* pass the baton */
            return addr;
        }
        sin_before = hal_sync_read_sin();
        (void)hal_wait_event_ms(DISCOVERY_SLEEP_MS, HAL_EV_I2C | HAL_EV_SIN_EDGE);
    }
}
