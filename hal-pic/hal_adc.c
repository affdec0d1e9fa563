/* hal-pic: 10-bit ADC on AN0..AN4 (RA0, RA1, RA2, RA3, RA5). The servos'
 * potentiometers take the first inputs (servo i on AN i), so channel k of
 * hal_adc_read is AN(HAL_PIC_SERVOS + k) and a build with s servos has
 * 5 - s channels (hal_pic_board.h). Vref = Vdd/Vss (5 V). A read converts the
 * channel on the spot (about 15 us): acquisition 4 TAD + 11 TAD, TAD = Fosc/16
 * = 0.8 us. */
#include "hal_adc.h"

#include "hal_pic.h"

#define ADC_CHANNELS (HP_BOARD_ANALOG_INPUTS - HAL_PIC_SERVOS)

void hp_adc_init(void)
{
    TRISA |= 0x2Fu;  /* RA0..RA3, RA5 inputs */
    ADCON1 = 0x0A;   /* Vss/Vdd references, AN0..AN4 analog, the rest digital */
    ADCON2 = 0x95;   /* right justified, ACQT 4 TAD, Fosc/16 */
    ADCON0 = 0x01;   /* ADON, channel 0 */
}

uint16_t hp_adc_convert(uint8_t an)
{
    ADCON0 = (uint8_t)((an << 2) | 0x01u);
    ADCON0bits.GO = 1;
    while (ADCON0bits.GO)
        ;
    return (uint16_t)(((uint16_t)ADRESH << 8) | ADRESL);
}

uint16_t hal_adc_read(uint8_t channel)
{
    if (channel >= ADC_CHANNELS)
        return 0;
    return hp_adc_convert((uint8_t)(HAL_PIC_SERVOS + channel));
}
