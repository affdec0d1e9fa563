/* hal-pic: encoder counters (traveller wheels): pulses on a pin, rising
 * edges, no direction (hal_pic_board.h):
 *   channel 0 = Timer0 on T0CKI (RA4), channel 1 = Timer1 on T13CKI (RC0),
 *   counted by the timers in external-clock mode; the 1 ms tick adds each
 *   16-bit timer's change to a 32-bit count (at most 65535 pulses per ms);
 *   channel 2, on a board without servos only = INT2 on RB2, counted by the
 *   low-priority interrupt (a few thousand pulses per second at most).
 * Other channels read 0. */
#include "hal_counter.h"

#include "hal_pic.h"

static volatile int32_t count0, count1;
static uint16_t last0, last1;
#if HAL_PIC_SERVOS == 0
static volatile int32_t count2;
#define COUNTERS 3u
#else
#define COUNTERS 2u
#endif

void hp_counter_init(void)
{
    TRISAbits.TRISA4 = 1;
    TRISCbits.TRISC0 = 1;
    TMR0H = 0;
    TMR0L = 0;
    T0CON = 0xA8;  /* TMR0ON, 16-bit, T0CKI, rising edge, no prescaler */
    TMR1H = 0;
    TMR1L = 0;
    T1CON = 0x83;  /* RD16, 1:1, oscillator off, synchronised, T13CKI, TMR1ON */
    last0 = 0;
    last1 = 0;
    count0 = 0;
    count1 = 0;
#if HAL_PIC_SERVOS == 0
    count2 = 0;
    TRISBbits.TRISB2 = 1;
    INTCON2bits.INTEDG2 = 1; /* rising edge */
    INTCON3bits.INT2IP = 0;  /* low priority */
    INTCON3bits.INT2IF = 0;
    INTCON3bits.INT2IE = 1;
#endif
}

void hp_counter_isr(void)
{
#if HAL_PIC_SERVOS == 0
    if (INTCON3bits.INT2IF) {
        INTCON3bits.INT2IF = 0;
        count2++;
    }
#endif
}

/* low-priority interrupt, every tick: 16-bit reads (TMRxL latches TMRxH) */
void hp_counter_tick(void)
{
    uint16_t now;
    now = TMR0L;
    now |= (uint16_t)TMR0H << 8;
    count0 += (uint16_t)(now - last0);
    last0 = now;
    now = TMR1L;
    now |= (uint16_t)TMR1H << 8;
    count1 += (uint16_t)(now - last1);
    last1 = now;
}

int32_t hal_counter_read(uint8_t channel)
{
    int32_t v;
    if (channel >= COUNTERS)
        return 0;
    INTCONbits.GIEL = 0;
#if HAL_PIC_SERVOS == 0
    v = channel == 0 ? count0 : channel == 1 ? count1 : count2;
#else
    v = channel == 0 ? count0 : count1;
#endif
    INTCONbits.GIEL = 1;
    return v;
}
