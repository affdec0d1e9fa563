/* hal-sim: analog inputs, as of the latest TICK_BEGIN. */
#include "hal_adc.h"

#include "hal_sim_link.h"

typedef char hs_adc_counts_check[(HAL_ADC_COUNTS_MAX == CS_ADC_COUNTS_MAX) ? 1 : -1];

uint16_t hal_adc_read(uint8_t channel)
{
    if (channel >= hs.n_adc || channel >= CS_ADC_MAX)
        return 0;
    return hs.adc[channel];
}
