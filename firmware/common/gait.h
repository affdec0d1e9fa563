/** @file
 * Travelling-wave gait arithmetic shared by the module programs (integer only).
 *
 *   phase(t)  = omega * t + offset                 [mrad, reduced to 0..6282]
 *   angle(t)  = A * sin(phase(t))                  [centidegrees]
 *
 * omega in mrad/s, t in ms (any uint32_t value: no overflow), offset in mrad
 * (the k * phase_step term of module k).
 */
#ifndef GAIT_H
#define GAIT_H

#include <stdint.h>

/** (omega_mrad_s * t_ms / 1000 + offset_mrad) modulo FS_TWO_PI_MRAD, 0..6282 */
int16_t gait_phase_mrad(int16_t omega_mrad_s, uint32_t t_ms, int32_t offset_mrad);

/** amp_cdeg * sin(gait_phase_mrad(...)), rounded */
int16_t gait_angle_cdeg(int16_t amp_cdeg, int16_t omega_mrad_s, uint32_t t_ms,
                        int32_t offset_mrad);

#endif
