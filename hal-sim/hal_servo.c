/* hal-sim: servomotors. Set-points are kept in millidegrees and sent in every
 * TICK_END with the enable mask; the measured angles come from TICK_BEGIN. */
#include "hal_servo.h"

#include "hal_sim_link.h"

/* the protocol carries as many servos as the HAL allows */
typedef char hs_servos_max_check[(HAL_SERVOS_MAX == CS_SERVOS_MAX) ? 1 : -1];

hal_status setspangle(uint8_t servo, int16_t angle_cdeg)
{
    if (servo >= hal_servo_count() || angle_cdeg < -HAL_SERVO_CDEG_MAX ||
        angle_cdeg > HAL_SERVO_CDEG_MAX)
        return HAL_ERR_ARG;
    hs.servo_setpoint[servo] = (int32_t)angle_cdeg * 10;
    hs.servo_enable |= (uint8_t)(1u << servo);
    return HAL_OK;
}

hal_status hal_servo_release(uint8_t servo)
{
    if (servo >= hal_servo_count())
        return HAL_ERR_ARG;
    hs.servo_enable &= (uint8_t)~(1u << servo);
    return HAL_OK;
}

int16_t hal_servo_angle_cdeg(uint8_t servo)
{
    int32_t mdeg, cdeg;
    if (servo >= hal_servo_count())
        return 0;
    mdeg = hs.servo_pos[servo];
    /* round to nearest, halves away from zero */
    cdeg = mdeg >= 0 ? (mdeg + 5) / 10 : -((-mdeg + 5) / 10);
    if (cdeg > 32767)
        cdeg = 32767;
    if (cdeg < -32768)
        cdeg = -32768;
    return (int16_t)cdeg;
}

uint8_t hal_servo_count(void)
{
    return hs.n_servos <= CS_SERVOS_MAX ? hs.n_servos : (uint8_t)CS_SERVOS_MAX;
}
