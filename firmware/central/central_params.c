/* The central control's parameters: see central_params.h. The table is the
 * one place their names, ranges, defaults and meanings are written; the
 * simulator checks a scene's central.params against it and
 * docs/firmware.md's table is checked against it (tests/tools/chainsim). */
#include "central_params.h"

#include "chain_commands.h"
#include "hal.h"

#define ROLL_SHIFT_MRAD 1571 /* shift_mrad of the roll when not given (pi/2) */

central_params params;

const hal_param_decl hal_param_table[] = {
    /* 10 (bend), 11 (hold), 12 (limp) are the elbow's own gaits and 13 is
     * gait 8 with inchworm_all: never a gait parameter */
    HAL_PARAM("gait", HAL_PARAM_U8, GAIT_NONE, GAIT_HELICOIDAL, GAIT_FORWARD,
              "0 none, 1 forward, 2 backward, 3 turn left, 4 turn right, 5 roll, 6 rotate in place, 7 lateral shift, "
              "8 inchworm, 9 helicoidal drive"),
    HAL_PARAM("amplitude_cdeg", HAL_PARAM_I16, 0, HAL_SERVO_CDEG_MAX, 4000, "amplitude A of the wave, cdeg"),
    HAL_PARAM("omega_mrad_s", HAL_PARAM_I16, -32767, 32767, 6000, "angular velocity w of the wave, mrad/s"),
    HAL_PARAM("phase_mrad", HAL_PARAM_I16, -32767, 32767, 1000, "phase step phi between consecutive modules, mrad"),
    HAL_PARAM("axis", HAL_PARAM_U8, CC_AXIS_PITCH, CC_AXIS_YAW, CC_AXIS_PITCH, "axis of the wave of gaits 1-4: 0 pitch, 1 yaw"),
    HAL_PARAM("posture_cdeg", HAL_PARAM_I16, -CC_QUARTER_TURN_CDEG, CC_QUARTER_TURN_CDEG, 0,
              "zig-zag posture P of the other axis, cdeg (+P/2 on module 0, -P odd, +P even)"),
    HAL_PARAM("amplitude2_cdeg", HAL_PARAM_I16, 0, HAL_SERVO_CDEG_MAX, 4000,
              "amplitude A2 of the yaw wave of roll, rotate, lateral shift, cdeg; not given: amplitude_cdeg"),
    HAL_PARAM("shift_mrad", HAL_PARAM_I16, -32767, 32767, 0,
              "phase psi of the yaw wave against the pitch wave (gaits 5-7), mrad; not given: 1571 for the roll, else 0"),
    HAL_PARAM("bias_cdeg", HAL_PARAM_I16, 0, CC_QUARTER_TURN_CDEG, 1000, "yaw offset B of the turns (gaits 3, 4), cdeg"),
    HAL_PARAM("start_ms", HAL_PARAM_U32, 0, 0x7FFFFFFFL, 0,
              "simulated time of START, ms; 0 or a time already passed: right after discovery"),
    HAL_PARAM("stop_ms", HAL_PARAM_U32, 0, 0x7FFFFFFFL, 0, "simulated time of STOP, ms; 0 = never"),
    HAL_PARAM("poll_ms", HAL_PARAM_U32, 0, 60000L, 0,
              "READ_SENSORS to every module every poll_ms, replies logged as 'sensors 0x20: ...'; 0 = never"),
    HAL_PARAM("drive_permille", HAL_PARAM_I16, -1000, 1000, 1000, "gait 9: the screw command, per mille (+ = forward)"),
    HAL_PARAM("step_ms", HAL_PARAM_I16, 40, 30000, 1000,
              "gait 8: duration of one step, ms (a cycle has one step per support, or two with inchworm_all)"),
    HAL_PARAM("inchworm_all", HAL_PARAM_U8, 0, 1, 0,
              "gait 8: 1 = every extension at once (paper 6.5; the tail support grips while all extend, the head "
              "while all retract), 0 = one support moves per step"),
    HAL_PARAM("grip_cdeg", HAL_PARAM_I16, 0, CC_QUARTER_TURN_CDEG, CC_QUARTER_TURN_CDEG,
              "gait 8: support arm angle when gripping, cdeg"),
    HAL_PARAM("stroke_um", HAL_PARAM_I16, 0, 15000, 15000, "gait 8: extension stroke, um"),
    HAL_PARAM("elbow_dir_deg", HAL_PARAM_I16, -2, 359, -1,
              "gait 9: way the next elbow turns, deg (0 up, 90 left, 180 down, 270 right), overriding the touch "
              "module's; -1 = sensed (away from where the touch module was touched); -2 = no steering"),
    HAL_PARAM("junction", HAL_PARAM_U8, 0, 2, 0,
              "gait 9: way taken where the touch module is pushed head-on (a wall ahead: a split, a tee): 0 none, "
              "1 left, 2 right (as gravity gives them; a follow-the-left-wall policy is 1)"),
    HAL_PARAM("bend_cdeg", HAL_PARAM_I16, 0, CC_QUARTER_TURN_CDEG, 4500,
              "gait 9: how far each rotation module bends toward the elbow, cdeg"),
    HAL_PARAM("bend_ms", HAL_PARAM_U16, 0, 30000, 1500, "gait 9: how long each rotation module holds the bend, ms"),
    HAL_PARAM("bend_travel_ms", HAL_PARAM_U16, 0, 30000, 0,
              "gait 9: the bend travels down the chain: a rotation module k places behind the first one bends "
              "k * bend_travel_ms after it, ms; 0 = all at once"),
    HAL_PARAM("bend_limp", HAL_PARAM_U8, 0, 1, 0,
              "gait 9: after bend_ms the rotation modules go limp (1: servos released, gait 12) instead of "
              "straightening (0)"),
    HAL_PARAM("hold_ms", HAL_PARAM_U16, 0, 30000, 0,
              "gait 9: from the bend the support modules grip the wall (gait 11, at grip_cdeg) and hold the "
              "chain for hold_ms (paper 6.6), ms; 0 = they never grip"),
    HAL_PARAM("stall_counts", HAL_PARAM_U16, 0, 1023, 0,
              "gait 9: the helicoidal modules' current (SENSORS, ADC counts; poll_ms) at or above this on two "
              "polls in a row is an elbow: the chain bends toward elbow_dir_deg; 0 = only the touch module's "
              "contact"),
    HAL_PARAM("switch_counts", HAL_PARAM_U16, 0, 1023, 0,
              "gait 9: a helicoidal module's current (ADC counts; poll_ms) at or above this on two polls in a row "
              "starts the supports' and extensions' inchworm, the screw still driving (6.7); 0 = never"),
    HAL_PARAM("switch_ms", HAL_PARAM_U16, 1, 30000, 6000,
              "gait 9 with switch_counts: how long the inchworm runs before the supports let go and the screw is "
              "tried alone again, ms"),
    HAL_PARAM_END
};

void central_params_read(void)
{
    params.gait = (uint8_t)hal_param("gait");
    params.amp_cdeg = (int16_t)hal_param("amplitude_cdeg");
    params.omega_mrad_s = (int16_t)hal_param("omega_mrad_s");
    params.phase_mrad = (int16_t)hal_param("phase_mrad");
    params.axis = (uint8_t)hal_param("axis");
    params.posture_cdeg = (int16_t)hal_param("posture_cdeg");
    /* two defaults depend on other parameters */
    params.amp2_cdeg = hal_param_given("amplitude2_cdeg") ? (int16_t)hal_param("amplitude2_cdeg") : params.amp_cdeg;
    params.shift_mrad = hal_param_given("shift_mrad") ? (int16_t)hal_param("shift_mrad")
                        : params.gait == GAIT_ROLL ? ROLL_SHIFT_MRAD : 0;
    params.bias_cdeg = (int16_t)hal_param("bias_cdeg");
    params.drive_permille = (int16_t)hal_param("drive_permille");
    params.step_ms = (int16_t)hal_param("step_ms");
    params.inchworm_all = (uint8_t)hal_param("inchworm_all");
    params.grip_cdeg = (int16_t)hal_param("grip_cdeg");
    params.stroke_um = (int16_t)hal_param("stroke_um");
    params.start_ms = (uint32_t)hal_param("start_ms");
    params.stop_ms = (uint32_t)hal_param("stop_ms");
    params.poll_ms = (uint32_t)hal_param("poll_ms");
    params.elbow_dir_deg = (int16_t)hal_param("elbow_dir_deg");
    params.junction = (uint8_t)hal_param("junction");
    params.bend_cdeg = (int16_t)hal_param("bend_cdeg");
    params.bend_ms = (uint16_t)hal_param("bend_ms");
    params.bend_travel_ms = (uint16_t)hal_param("bend_travel_ms");
    params.bend_limp = (uint8_t)hal_param("bend_limp");
    params.hold_ms = (uint16_t)hal_param("hold_ms");
    params.stall_counts = (uint16_t)hal_param("stall_counts");
    params.switch_counts = (uint16_t)hal_param("switch_counts");
    params.switch_ms = (uint16_t)hal_param("switch_ms");
}
