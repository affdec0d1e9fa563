/** @file
 * Where a touch module was touched: its cover rests on contact switches
 * around the module's axis (scenes/modules/touch.yaml: three, 120 degrees
 * apart), and the switches that closed tell the direction of the obstacle
 * in the module's own frame; the accelerometer's gravity tells where "up"
 * is in that frame, so the direction can also be named up, left, down or
 * right. Integer only (the PIC18 build); part of fw-touch only (the
 * central control reads the results from the TOUCH frame).
 *
 * Angles are whole degrees about the module's x axis (forward), 0 = the
 * module's up (+z), 90 = its left (+y), 180 = down, 270 = right: the
 * convention of fw-central's elbow_dir_deg.
 */
#ifndef TOUCH_DIRECTION_H
#define TOUCH_DIRECTION_H

#include <stdint.h>

#include "chain_commands.h"

#define TD_NONE CC_TOUCH_NONE /**< no direction: nothing touched, or a push along the axis (every switch) */

/** atan2(y, x) in whole degrees 0..359 (0 along +x, 90 along +y): within
 * 0.3 degree before the rounding to whole degrees (tests/firmware/touch/
 * touch_direction_test.cpp); TD_NONE when both are 0 */
int16_t td_atan2_deg(int16_t y, int16_t x);

/** the obstacle's direction from the switches that closed (bit k = switch
 * k, at first_deg + k * 360 / n): the mean of their directions; TD_NONE
 * when none closed or they balance (all three: pushed head-on) */
int16_t td_direction(uint8_t closed, uint8_t n, int16_t first_deg);

/** where "up" (against gravity) lies about the module's axis, in the same
 * degrees, from the accelerometer's y (left) and z (up) readings in ADC
 * counts (zero_counts = 0 g); TD_NONE when gravity is along the axis */
int16_t td_up_deg(int16_t y_counts, int16_t z_counts, int16_t zero_counts);

/** a direction in the module frame as seen from the world: 0 above, 90 on
 * the left, 180 below, 270 on the right (dir - up, wrapped); TD_NONE when
 * either is */
int16_t td_world_deg(int16_t dir_deg, int16_t up_deg);

/** the side nearest a world direction: CC_SIDE_UP, _LEFT, _DOWN, _RIGHT
 * (CC_SIDE_NONE for TD_NONE) */
uint8_t td_side(int16_t world_deg);

#endif
