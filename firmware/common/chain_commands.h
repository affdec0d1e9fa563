/** @file
 * The chain's I2C command set (central control <-> modules).
 *
 * Every frame: byte 0 = command code, then the arguments, integers
 * little-endian. Replies go to the central control's address
 * CHAIN_CENTRAL_ADDR. Modules get addresses CHAIN_FIRST_MODULE_ADDR + k,
 * k = 0.. in chain order, during discovery (docs/firmware.md).
 *
 *  code  name            dir        to       bytes  layout
 *  0x01  ENUM_OFFER      C -> M     general  2      code, addr
 *  0x02  ENUM_REPLY      M -> C     0x10     3      code, addr, type
 *  0x10  SET_GAIT        C -> M     module   17     code, gait, amp_cdeg i16,
 *                                                   omega_mrad_s i16, phase_mrad i16, axis,
 *                                                   posture_cdeg i16, amp2_cdeg i16,
 *                                                   shift_mrad i16, bias_cdeg i16
 *  0x11  START           C -> M     general  1      code
 *  0x12  STOP            C -> M     any      1      code
 *  0x20  READ_SENSORS    C -> M     module   1      code
 *  0x21  SENSORS         M -> C     0x10     3+2n   code, addr, n, n x angle_cdeg i16
 *  0x22  STATUS          C -> M     module   1      code
 *  0x23  STATUS_REPLY    M -> C     0x10     6      code, addr, type, state, gait, flags
 *  0x24  TOUCH           M -> C     0x10     3      code, addr, contact (touch module, on change)
 *
 * SET_GAIT of gaits 8 to 11 reuses the frame's fields (CC_GAIT_OFF_DRIVE ..
 * CC_GAIT_OFF_STROKE below); gait 12 has none.
 *
 * Modules ignore codes they do not know and frames of the wrong length
 * (STATUS_REPLY then shows CC_FLAG_BAD_FRAME).
 */
#ifndef CHAIN_COMMANDS_H
#define CHAIN_COMMANDS_H

#include <stdint.h>

/** the central control's address (7-bit): where replies go */
#define CHAIN_CENTRAL_ADDR 0x10u
#define CHAIN_FIRST_MODULE_ADDR 0x20u /**< module k's address is this + k (discovery) */
#define CHAIN_MAX_MODULES 32u /**< addresses 0x20..0x3F */

/* command codes (byte 0 of a frame) and frame lengths in bytes: the table above */
#define CC_ENUM_OFFER 0x01u   /**< C -> M, general call: code, addr: the unaddressed module that holds the discovery baton (its Sin line: docs/firmware.md, "Discovery") takes addr */
#define CC_ENUM_REPLY 0x02u   /**< M -> C: code, addr, type (MT_*): taken */
#define CC_SET_GAIT 0x10u     /**< C -> M: the gait and its parameters (CC_GAIT_OFF_*) */
#define CC_START 0x11u        /**< C -> M, general call: start the gait clock, every module at the same tick */
#define CC_STOP 0x12u         /**< C -> M: stop, servos to 0 */
#define CC_READ_SENSORS 0x20u /**< C -> M: ask for the servo angles */
#define CC_SENSORS 0x21u      /**< M -> C: code, addr, n, n servo angles (i16, cdeg) */
#define CC_STATUS 0x22u       /**< C -> M: ask for the state */
#define CC_STATUS_REPLY 0x23u /**< M -> C: code, addr, type, state (CC_STATE_*), gait, flags (CC_FLAG_*) */
#define CC_TOUCH 0x24u        /**< M -> C: code, addr, switches closed (bit k = switch k; 0 = released), the obstacle's direction and where up is (i16 deg each, CC_TOUCH_NONE: none) and the obstacle's side (CC_SIDE_*), when the switches change (a touch module; firmware/touch/touch_direction.h) */

#define CC_ENUM_OFFER_LEN 2u          /**< bytes of an ENUM_OFFER frame */
#define CC_ENUM_REPLY_LEN 3u          /**< bytes of an ENUM_REPLY frame */
#define CC_SET_GAIT_LEN 17u           /**< bytes of a SET_GAIT frame */
#define CC_START_LEN 1u               /**< bytes of a START frame */
#define CC_STOP_LEN 1u                /**< bytes of a STOP frame */
#define CC_READ_SENSORS_LEN 1u        /**< bytes of a READ_SENSORS frame */
#define CC_SENSORS_LEN(n) (3u + 2u * (n)) /**< bytes of a SENSORS frame of n angles */
#define CC_STATUS_LEN 1u              /**< bytes of a STATUS frame */
#define CC_STATUS_REPLY_LEN 6u        /**< bytes of a STATUS_REPLY frame */
#define CC_TOUCH_LEN 8u               /**< bytes of a TOUCH frame */
#define CC_TOUCH_OFF_DIR 3u           /**< TOUCH: the obstacle's direction about the module's axis, i16 deg (0 = the module's top, 90 its left) */
#define CC_TOUCH_OFF_UP 5u            /**< TOUCH: where up (against gravity) is about the module's axis, i16 deg */
#define CC_TOUCH_OFF_SIDE 7u          /**< TOUCH: the obstacle's side as the world sees it, CC_SIDE_* */
#define CC_TOUCH_NONE (-1)            /**< TOUCH: no direction (released, a push along the axis, gravity along it) */
#define CC_SIDE_UP 0u                 /**< TOUCH side: above */
#define CC_SIDE_LEFT 1u               /**< on the left */
#define CC_SIDE_DOWN 2u               /**< below */
#define CC_SIDE_RIGHT 3u              /**< on the right */
#define CC_SIDE_NONE 255u             /**< unknown */

/** the limit of the angle fields that bend a joint one way (posture, bias,
 * bend, grip): a quarter turn, in centidegrees. The amplitudes may reach the
 * HAL's set-point limit, HAL_SERVO_CDEG_MAX (hal_servo.h). */
#define CC_QUARTER_TURN_CDEG 9000

/** SET_GAIT byte offsets */
#define CC_GAIT_OFF_GAIT 1u
#define CC_GAIT_OFF_AMP 2u   /**< i16 amplitude, centidegrees (0..18000) */
#define CC_GAIT_OFF_OMEGA 4u /**< i16 angular velocity, mrad/s */
#define CC_GAIT_OFF_PHASE 6u /**< i16 phase step between consecutive modules, mrad */
#define CC_GAIT_OFF_AXIS 8u  /**< CC_AXIS_* */
/** i16 zig-zag posture of the other axis, centidegrees: module k holds its
 * other servo at +P/2 (k = 0), -P (k odd), +P (k even), so the chain's links
 * alternate +-P/2 about its axis; spreads the ground contacts of a vertical
 * wave so the round modules do not roll over (0 = straight) */
#define CC_GAIT_OFF_POSTURE 9u
/** the two-axis gaits (roll, rotate, lateral shift) and the turns; a sender
 * that leaves these 0 gets the forward/backward gaits unchanged */
#define CC_GAIT_OFF_AMP2 11u  /**< i16 amplitude of the yaw wave, centidegrees (0..18000) */
#define CC_GAIT_OFF_SHIFT 13u /**< i16 phase of the yaw wave relative to the pitch wave, mrad */
#define CC_GAIT_OFF_BIAS 15u  /**< i16 yaw offset of a turn, centidegrees (0..9000) */

/** SET_GAIT of gait 9 (helicoidal drive), sent to helicoidal modules */
#define CC_GAIT_OFF_DRIVE 2u  /**< i16 screw command, per mille (-1000..1000, + = forward) */
/** SET_GAIT of gait 10 (bend), sent to rotation modules: the angles to hold */
#define CC_GAIT_OFF_BEND_PITCH 2u /**< i16 pitch, centidegrees (-9000..9000) */
#define CC_GAIT_OFF_BEND_YAW 4u   /**< i16 yaw, centidegrees (-9000..9000) */
/** SET_GAIT of gait 11 (hold), sent to support modules: the arms open to
 * the grip angle at CC_GAIT_OFF_GRIP (below) at once and hold; gait 0
 * closes them. Gait 12 (limp), sent to rotation modules, has no fields. */
/** SET_GAIT of gait 8 (inchworm), sent to support and extension modules, one
 * frame each: the cycle has n steps (one per support); in step i support i
 * releases, extension i-1 retracts and extension i extends, then support i
 * grips again (docs/firmware.md). Gait 13 (every extension at once) has the
 * same fields: its cycle is 2 steps, the tail support gripping while all
 * the extensions extend, then the head while they retract (inchworm.h) */
#define CC_GAIT_OFF_GRIP 2u   /**< i16 support arm angle when gripping, cdeg (0..9000) */
#define CC_GAIT_OFF_STEP 4u   /**< i16 duration of one step, ms (>= 40) */
#define CC_GAIT_OFF_INDEX 6u  /**< i16 this module's index among the supports / extensions */
#define CC_GAIT_OFF_NSUP 8u   /**< u8 number of supports n = steps per cycle */
#define CC_GAIT_OFF_STROKE 9u /**< i16 extension stroke, um (0..15000) */

/* module type codes (ENUM_REPLY, STATUS_REPLY); the chain line's letter in parentheses */
#define MT_ROTATION 1u   /**< rotation module, two servos, pitch and yaw (R) */
#define MT_HELICOIDAL 2u /**< helicoidal drive: a screw turned by a motor (H) */
#define MT_SUPPORT 3u    /**< support: arms that grip the pipe wall (S) */
#define MT_EXTENSION 4u  /**< extension: a linear stroke (E) */
#define MT_TOUCH 5u      /**< touch module at the head: contact sensors (T) */
#define MT_TRAVELLER 6u  /**< traveller: wheels that count the distance (W) */
#define MT_PASSIVE 7u    /**< passive module: no actuator (P) */

/** gait codes (SET_GAIT) */
#define GAIT_NONE 0u          /**< stop, servos to 0 */
#define GAIT_FORWARD 1u       /**< travelling sine wave, phase +k*phase */
#define GAIT_BACKWARD 2u      /**< the wave the other way, phase -k*phase */
#define GAIT_TURN_LEFT 3u     /**< the forward wave + a yaw offset bending the chain left */
#define GAIT_TURN_RIGHT 4u    /**< the same, bent right */
#define GAIT_ROLL 5u          /**< pitch and yaw waves shifted 90 deg, phase step 0 */
#define GAIT_ROTATE 6u        /**< pitch wave of twice the yaw wave's phase step */
#define GAIT_LATERAL_SHIFT 7u /**< pitch and yaw waves of the same phase step, shifted */
#define GAIT_INCHWORM 8u      /**< supports grip/release, extensions extend/retract */
#define GAIT_HELICOIDAL 9u    /**< helicoidal modules drive their screws */
#define GAIT_BEND 10u         /**< rotation modules hold a fixed pitch and yaw (elbows) */
#define GAIT_HOLD 11u         /**< support modules grip the wall and hold, at once (paper 6.6's support holding the robot) */
#define GAIT_LIMP 12u         /**< rotation modules release their servos (no pulses: the joints go limp) */
#define GAIT_INCHWORM_ALL 13u /**< the inchworm with every extension at once (paper 6.5): one support grips, the rest move */

/** axis (SET_GAIT): which servo of a rotation module moves */
#define CC_AXIS_PITCH 0u /**< servo 0 */
#define CC_AXIS_YAW 1u   /**< servo 1 */

/* STATUS_REPLY state */
#define CC_STATE_IDLE 0u    /**< no gait running (before START, after STOP) */
#define CC_STATE_RUNNING 1u /**< a gait is running */

/** STATUS_REPLY flags (sticky until read by STATUS) */
#define CC_FLAG_BAD_GAIT 0x01u  /**< a gait or axis this module can't do */
#define CC_FLAG_BAD_FRAME 0x02u /**< unknown code or wrong length */
#define CC_FLAG_SERVO 0x04u     /**< setspangle refused a value */
#define CC_FLAG_TOUCH 0x08u     /**< touch module: contact since the last STATUS */

/** write v at p, little-endian (2 bytes) */
void cc_put_i16(uint8_t *p, int16_t v);
/** the little-endian int16 at p */
int16_t cc_get_i16(const uint8_t *p);

/** letter for a module type in the chain line: T R H S E W P, '?' if unknown */
char cc_type_letter(uint8_t type);

#endif
