/* Shared module-program runtime: see chain_app.h. */
#include "chain_app.h"

#include "chain_commands.h"
#include "chain_module.h"
#include "hal.h"

#define CA_IDLE_SLEEP_MS 60000u
#define CA_SENSORS_MAX 6u

uint8_t ca_addr;
uint8_t ca_pos;
uint8_t ca_type;
uint8_t ca_running;
uint8_t ca_gait;
uint8_t ca_flags;
uint16_t ca_control_ms;

static uint32_t ca_t0_ms;
static uint32_t ca_next_ms;

void chain_app_init(uint8_t type)
{
    ca_control_ms = (uint16_t)hal_param("control_ms"); /* 1..1000: the declaration's range */
    ca_type = type;
    ca_addr = chain_module_discover(type);
    ca_pos = (uint8_t)(ca_addr - CHAIN_FIRST_MODULE_ADDR);
    ca_next_ms = hal_millis();
}

uint8_t chain_app_take_gait(const uint8_t *buf, uint8_t supported)
{
    ca_gait = buf[CC_GAIT_OFF_GAIT];
    if (ca_gait != GAIT_NONE && ca_gait != supported)
        ca_flags |= CC_FLAG_BAD_GAIT;
    return ca_gait;
}

void chain_app_reply(const uint8_t *data, uint8_t len)
{
    while (hal_i2c_send(CHAIN_CENTRAL_ADDR, data, len) == HAL_ERR_FULL)
        hal_tick_wait();
}

void chain_app_sensors(const int16_t *v, uint8_t n)
{
    uint8_t out[CC_SENSORS_LEN(CA_SENSORS_MAX)];
    uint8_t i;
    if (n > CA_SENSORS_MAX)
        n = CA_SENSORS_MAX;
    out[0] = CC_SENSORS;
    out[1] = ca_addr;
    out[2] = n;
    for (i = 0; i < n; i++)
        cc_put_i16(out + 3u + 2u * i, v[i]);
    chain_app_reply(out, (uint8_t)CC_SENSORS_LEN(n));
}

void chain_app_servo(uint8_t servo, int16_t cdeg)
{
    if (servo >= hal_servo_count())
        return;
    if (setspangle(servo, cdeg) != HAL_OK)
        ca_flags |= CC_FLAG_SERVO;
}

uint8_t chain_app_filter(const uint8_t *buf, uint8_t len, uint8_t to)
{
    uint8_t out[CC_STATUS_REPLY_LEN];
    uint8_t want = 0;

    if (len == 0 || (to != ca_addr && to != HAL_I2C_GENERAL_CALL))
        return 0;
    switch (buf[0]) {
    case CC_ENUM_OFFER:
        return 0; /* already addressed */
    case CC_SET_GAIT: want = CC_SET_GAIT_LEN; break;
    case CC_START: want = CC_START_LEN; break;
    case CC_STOP: want = CC_STOP_LEN; break;
    case CC_READ_SENSORS:
        if (to != ca_addr)
            want = 0; /* never by general call */
        else
            want = CC_READ_SENSORS_LEN;
        break;
    case CC_STATUS:
        if (len != CC_STATUS_LEN || to != ca_addr)
            break;
        out[0] = CC_STATUS_REPLY;
        out[1] = ca_addr;
        out[2] = ca_type;
        out[3] = ca_running ? CC_STATE_RUNNING : CC_STATE_IDLE;
        out[4] = ca_gait;
        out[5] = ca_flags;
        ca_flags = 0;
        chain_app_reply(out, CC_STATUS_REPLY_LEN);
        return 0;
    default:
        want = 0;
        break;
    }
    if (want != 0 && len == want)
        return buf[0];
    ca_flags |= CC_FLAG_BAD_FRAME;
    return 0;
}

void chain_app_clock_start(void)
{
    ca_t0_ms = hal_millis();
    ca_next_ms = ca_t0_ms;
}

uint32_t chain_app_clock_ms(void)
{
    return hal_millis() - ca_t0_ms;
}

void chain_app_step_now(void)
{
    ca_next_ms = hal_millis();
}

uint8_t chain_app_wait(uint8_t periodic)
{
    uint32_t now = hal_millis();
    if (periodic && (int32_t)(now - ca_next_ms) >= 0) {
        ca_next_ms += ca_control_ms;
        if ((int32_t)(now - ca_next_ms) >= 0) /* fell behind: resync */
            ca_next_ms = now + ca_control_ms;
        return 1;
    }
    (void)hal_wait_event_ms(periodic ? (uint16_t)(ca_next_ms - now) : CA_IDLE_SLEEP_MS, HAL_EV_I2C);
    return 0;
}
