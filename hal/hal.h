/** @file
 * The chainsim HAL: the only interface module firmware includes.
 * The same firmware links with hal-sim (a simulator process) or hal-pic (the
 * PIC18 board); it cannot tell which. C99, no dynamic memory. */
#ifndef HAL_H
#define HAL_H

#include "hal_status.h"
#include "hal_time.h"
#include "hal_servo.h"
#include "hal_i2c.h"
#include "hal_sync.h"
#include "hal_adc.h"
#include "hal_gpio.h"
#include "hal_counter.h"
#include "hal_log.h"
#include "hal_param.h"

#endif
