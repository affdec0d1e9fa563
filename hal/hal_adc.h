/** @file
 * Analog inputs: 10-bit converter, 0..HAL_ADC_VREF_MV. */
#ifndef HAL_ADC_H
#define HAL_ADC_H

#include <stdint.h>

#define HAL_ADC_VREF_MV 5000u   /**< the reference: HAL_ADC_COUNTS_MAX counts, mV */
#define HAL_ADC_COUNTS_MAX 1023u /**< a full-scale reading (10 bits) */

/** last conversion of channel in counts (0 for a channel the module lacks) */
uint16_t hal_adc_read(uint8_t channel);

#endif
