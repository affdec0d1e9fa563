/* The gait commands: see gaits.h. */
#include "gaits.h"

#include "central_io.h"
#include "central_params.h"
#include "chain_commands.h"
#include "discovery.h"
#include "hal.h"

static uint8_t frame[CC_SET_GAIT_LEN];

/* a SET_GAIT frame of gait with every field 0 */
static void frame_clear(uint8_t gait)
{
    uint8_t i;
    for (i = 0; i < CC_SET_GAIT_LEN; i++)
        frame[i] = 0;
    frame[0] = CC_SET_GAIT;
    frame[CC_GAIT_OFF_GAIT] = gait;
}

void gaits_log(void)
{
    sb_reset(&cio_sb);
    cio_put("gait: code=", params.gait);
    cio_put(" amp_cdeg=", params.amp_cdeg);
    cio_put(" omega_mrad_s=", params.omega_mrad_s);
    cio_put(" phase_mrad=", params.phase_mrad);
    cio_put(" axis=", params.axis);
    cio_put(" posture_cdeg=", params.posture_cdeg);
    cio_log_line(cio_sb.buf);
    if (params.gait == GAIT_HELICOIDAL) {
        cio_log_int("gait: drive_permille=", (uint32_t)(int32_t)params.drive_permille);
    } else if (params.gait == GAIT_INCHWORM) {
        sb_reset(&cio_sb);
        cio_put("gait: step_ms=", params.step_ms);
        cio_put(" grip_cdeg=", params.grip_cdeg);
        cio_put(" stroke_um=", params.stroke_um);
        if (params.inchworm_all)
            sb_str(&cio_sb, " every extension at once");
        cio_log_line(cio_sb.buf);
    } else if (params.gait >= GAIT_TURN_LEFT) {
        sb_reset(&cio_sb);
        cio_put("gait: amp2_cdeg=", params.amp2_cdeg);
        cio_put(" shift_mrad=", params.shift_mrad);
        cio_put(" bias_cdeg=", params.bias_cdeg);
        cio_log_line(cio_sb.buf);
    }
}

/* gaits 1-7: the wave, to every rotation module */
static void send_wave(void)
{
    frame_clear(params.gait);
    cc_put_i16(frame + CC_GAIT_OFF_AMP, params.amp_cdeg);
    cc_put_i16(frame + CC_GAIT_OFF_OMEGA, params.omega_mrad_s);
    cc_put_i16(frame + CC_GAIT_OFF_PHASE, params.phase_mrad);
    frame[CC_GAIT_OFF_AXIS] = params.axis;
    cc_put_i16(frame + CC_GAIT_OFF_POSTURE, params.posture_cdeg);
    cc_put_i16(frame + CC_GAIT_OFF_AMP2, params.amp2_cdeg);
    cc_put_i16(frame + CC_GAIT_OFF_SHIFT, params.shift_mrad);
    cc_put_i16(frame + CC_GAIT_OFF_BIAS, params.bias_cdeg);
    chain_send_to_type(MT_ROTATION, frame, CC_SET_GAIT_LEN);
}

/* gait 9: the screw command (per mille) to every helicoidal module */
static void send_helicoidal(void)
{
    frame_clear(GAIT_HELICOIDAL);
    cc_put_i16(frame + CC_GAIT_OFF_DRIVE, params.drive_permille);
    chain_send_to_type(MT_HELICOIDAL, frame, CC_SET_GAIT_LEN);
}

/* gait 8 or 13: every support and extension gets the schedule and its
 * index (supports and extensions counted separately, head first) */
void gaits_send_inchworm(uint8_t gait)
{
    uint8_t i, n_sup = 0, k_sup = 0, k_ext = 0;

    for (i = 0; i < chain_n_modules; i++)
        if (chain_module_type[i] == MT_SUPPORT)
            n_sup++;
    frame_clear(gait);
    cc_put_i16(frame + CC_GAIT_OFF_GRIP, params.grip_cdeg);
    cc_put_i16(frame + CC_GAIT_OFF_STEP, params.step_ms);
    frame[CC_GAIT_OFF_NSUP] = n_sup;
    cc_put_i16(frame + CC_GAIT_OFF_STROKE, params.stroke_um);
    for (i = 0; i < chain_n_modules; i++) {
        if (chain_module_type[i] == MT_SUPPORT)
            cc_put_i16(frame + CC_GAIT_OFF_INDEX, (int16_t)k_sup++);
        else if (chain_module_type[i] == MT_EXTENSION)
            cc_put_i16(frame + CC_GAIT_OFF_INDEX, (int16_t)k_ext++);
        else
            continue;
        cio_send((uint8_t)(CHAIN_FIRST_MODULE_ADDR + i), frame, CC_SET_GAIT_LEN);
    }
}

void gaits_send(void)
{
    if (params.gait == GAIT_HELICOIDAL)
        send_helicoidal();
    else if (params.gait == GAIT_INCHWORM)
        gaits_send_inchworm(params.inchworm_all ? GAIT_INCHWORM_ALL : GAIT_INCHWORM);
    else
        send_wave();
}

void gaits_send_bend(uint8_t module, int16_t pitch_cdeg, int16_t yaw_cdeg)
{
    frame_clear(GAIT_BEND);
    cc_put_i16(frame + CC_GAIT_OFF_BEND_PITCH, pitch_cdeg);
    cc_put_i16(frame + CC_GAIT_OFF_BEND_YAW, yaw_cdeg);
    cio_send((uint8_t)(CHAIN_FIRST_MODULE_ADDR + module), frame, CC_SET_GAIT_LEN);
}

void gaits_send_hold(uint8_t hold)
{
    frame_clear(hold ? GAIT_HOLD : GAIT_NONE);
    cc_put_i16(frame + CC_GAIT_OFF_GRIP, params.grip_cdeg);
    chain_send_to_type(MT_SUPPORT, frame, CC_SET_GAIT_LEN);
}

void gaits_send_none(uint8_t type)
{
    frame_clear(GAIT_NONE);
    chain_send_to_type(type, frame, CC_SET_GAIT_LEN);
}

void gaits_send_limp(uint8_t module)
{
    frame_clear(GAIT_LIMP);
    cio_send((uint8_t)(CHAIN_FIRST_MODULE_ADDR + module), frame, CC_SET_GAIT_LEN);
}
