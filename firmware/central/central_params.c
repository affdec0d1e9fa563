/* The central control's parameters: see central_params.h. */
#include "central_params.h"

#include "chain_commands.h"
#include "hal.h"

#define ROLL_SHIFT_MRAD 1571   /* default shift_mrad of the roll (pi/2); 0 for the others */
#define BIAS_DEFAULT_CDEG 1000 /* default bias_cdeg: yaw offset of the turns */

central_params params;

static int32_t param_clamped(const char *name, int32_t def, int32_t lo, int32_t hi)
{
    int32_t v = hal_param(name, def);
    if (v < lo)
        return lo;
    if (v > hi)
        return hi;
    return v;
}

void central_params_read(void)
{
    params.gait = (uint8_t)param_clamped("gait", GAIT_FORWARD, 0, 255);
    params.amp_cdeg = (int16_t)param_clamped("amplitude_cdeg", 4000, 0, HAL_SERVO_CDEG_MAX);
    params.omega_mrad_s = (int16_t)param_clamped("omega_mrad_s", 6000, -32767, 32767);
    params.phase_mrad = (int16_t)param_clamped("phase_mrad", 1000, -32767, 32767);
    params.axis = (uint8_t)param_clamped("axis", CC_AXIS_PITCH, CC_AXIS_PITCH, CC_AXIS_YAW);
    params.posture_cdeg = (int16_t)param_clamped("posture_cdeg", 0, -CC_QUARTER_TURN_CDEG,
                                             CC_QUARTER_TURN_CDEG);
    /* the two-axis gaits and the turns; two defaults depend on other
     * parameters (amplitude2 on amplitude, shift on the gait) */
    params.amp2_cdeg = (int16_t)param_clamped("amplitude2_cdeg", params.amp_cdeg, 0, HAL_SERVO_CDEG_MAX);
    params.shift_mrad = (int16_t)param_clamped("shift_mrad",
                                           params.gait == GAIT_ROLL ? ROLL_SHIFT_MRAD : 0, -32767,
                                           32767);
    params.bias_cdeg = (int16_t)param_clamped("bias_cdeg", BIAS_DEFAULT_CDEG, 0, CC_QUARTER_TURN_CDEG);
    params.drive_permille = (int16_t)param_clamped("drive_permille", 1000, -1000, 1000);
    params.step_ms = (int16_t)param_clamped("step_ms", 1000, 40, 30000);
    params.grip_cdeg = (int16_t)param_clamped("grip_cdeg", CC_QUARTER_TURN_CDEG, 0,
                                          CC_QUARTER_TURN_CDEG);
    params.stroke_um = (int16_t)param_clamped("stroke_um", 15000, 0, 15000);
    params.start_ms = (uint32_t)param_clamped("start_ms", 0, 0, 0x7FFFFFFFL);
    params.stop_ms = (uint32_t)param_clamped("stop_ms", 0, 0, 0x7FFFFFFFL);
    params.poll_ms = (uint32_t)param_clamped("poll_ms", 0, 0, 60000L);
    params.elbow_dir_deg = (int16_t)param_clamped("elbow_dir_deg", -1, -1, 359);
    params.bend_cdeg = (int16_t)param_clamped("bend_cdeg", 4500, 0, CC_QUARTER_TURN_CDEG);
    params.bend_ms = (uint16_t)param_clamped("bend_ms", 1500, 0, 30000L);
}
