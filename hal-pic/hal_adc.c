/* hal-pic: 10-bit ADC. Channels 0..4 are AN0..AN4 (RA0, RA1, RA2, RA3, RA5);
 * AN0/AN1 are also the servo potentiometers. Vref = Vdd/Vss (5 V). A read
 * converts the channel on the spot (about 15 us): acquisition 4 TAD + 11 TAD,
 * TAD = Fosc/16 = 0.8 us. */
#include "hal_adc.h"

#include "hal_pic.h"

#define ADC_CHANNELS 5u

void hp_adc_init(void)
{
    TRISA |= 0x2Fu;  /* RA0..RA3, RA5 inputs */
    ADCON1 = 0x0A;   /* Vss/Vdd references, AN0..AN4 analog, the rest digital */
    ADCON2 = 0x95;   /* right justified, ACQT 4 TAD, Fosc/16 */
    ADCON0 = 0x01;   /* ADON, channel 0 */
}

uint16_t hal_adc_read(uint8_t channel)
{
    if (channel >= ADC_CHANNELS)
        return 0;
    ADCON0 = (uint8_t)((channel << 2) | 0x01u);
    ADCON0bits.GO = 1;
    while (ADCON0bits.GO)
        ;
    return (uint16_t)(((uint16_t)ADRESH << 8) | ADRESL);
}
