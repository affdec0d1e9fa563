/** @file
 * Fixed-point sine for the module firmware: no floating point, one 65-entry
 * quarter-wave table of int16 (130 bytes of ROM), linear interpolation.
 *
 *   angles:  binary angle (BAM16, 65536 = one turn) or milliradians
 *   output:  Q15, i.e. -32767..32767 for -1..1
 *
 * Accuracy (checked by tests/firmware/common/fixed_sin_test.cpp against sin()):
 *   fs_sin_bam   |error| <= 1.0e-4 (measured 9.5e-5, 3.2 Q15 counts)
 *   fs_sin_mrad  |error| <= 3.0e-4 (measured 2.5e-4); it uses a period of exactly
 *                FS_TWO_PI_MRAD = 6283 mrad instead of 6283.185, which costs
 *                at most 0.185 mrad of phase near the end of the turn.
 */
#ifndef FIXED_SIN_H
#define FIXED_SIN_H

#include <stdint.h>

#define FS_ONE_Q15 32767       /**< sin(pi/2) */
#define FS_TWO_PI_MRAD 6283L   /**< one turn in milliradians (the period used here) */

/** sin of a binary angle (0x4000 = pi/2), Q15 */
int16_t fs_sin_bam(uint16_t angle);

/** sin of an angle in milliradians (any value, reduced modulo FS_TWO_PI_MRAD), Q15 */
int16_t fs_sin_mrad(int32_t angle_mrad);

/** cos of an angle in milliradians, Q15 */
int16_t fs_cos_mrad(int32_t angle_mrad);

/** angle_mrad reduced to 0..FS_TWO_PI_MRAD-1 */
int16_t fs_wrap_mrad(int32_t angle_mrad);

/** amplitude * q15 / 32768, rounded to nearest (halves away from zero);
 * e.g. fs_scale(4000, fs_sin_mrad(x)) is 4000*sin(x) */
int16_t fs_scale(int16_t amplitude, int16_t q15);

#endif
