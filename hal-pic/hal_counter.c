/* hal-pic: encoder counters (traveller wheels): pulses on a pin, rising
 * edges, no direction (hal_pic_board.h):
 *   channel 0 = Timer1 on T13CKI (RC0), counted by the timer in
 *     external-clock mode; the 1 ms tick adds its 16-bit change to a 32-bit
 *     count (at most 65535 pulses per ms);
 *   channel 1, on a board with at most 2 servos = RB4, counted by the
 *     interrupt on change of port B;
 *   channel 2, on a board without servos = INT2 on RB2, counted by the
 *     interrupt;
 * both interrupts low priority (a few thousand pulses per second at most).
 * Other channels read 0. (Timer0 on T0CKI would count on the part too, but
 * gpsim 0.31 runs the PIC18's Timer0 on the instruction clock whatever
 * T0CS says: a counter there could not be simulated. docs/pic-in-the-loop.md) */
#include "hal_counter.h"

#include "hal_pic.h"

static volatile int32_t count0;
static uint16_t last0;
#if HAL_PIC_SERVOS <= 2
static volatile int32_t count1;
static uint8_t rb4_was;
#endif
#if HAL_PIC_SERVOS == 0
static volatile int32_t count2;
#endif
#define COUNTERS HP_BOARD_COUNTERS(HAL_PIC_SERVOS)

void hp_counter_init(void)
{
    TRISCbits.TRISC0 = 1;
    TMR1H = 0;
    TMR1L = 0;
    T1CON = 0x83;  /* RD16, 1:1, oscillator off, synchronised, T13CKI, TMR1ON */
    last0 = 0;
    count0 = 0;
#if HAL_PIC_SERVOS <= 2
    count1 = 0;
    TRISBbits.TRISB4 = 1;
    rb4_was = PORTBbits.RB4; /* reading port B ends a mismatch */
    INTCON2bits.RBIP = 0;    /* low priority */
    INTCONbits.RBIF = 0;
    INTCONbits.RBIE = 1;
#endif
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
#if HAL_PIC_SERVOS <= 2
    if (INTCONbits.RBIE && INTCONbits.RBIF) {
        uint8_t now = PORTBbits.RB4; /* also the touch inputs RB6, RB7 change port B */
        INTCONbits.RBIF = 0;
        if (now && !rb4_was)
            count1++;
        rb4_was = now;
    }
#endif
#if HAL_PIC_SERVOS == 0
    if (INTCON3bits.INT2IF) {
        INTCON3bits.INT2IF = 0;
        count2++;
    }
#endif
}

/* low-priority interrupt, every tick: a 16-bit read (TMR1L latches TMR1H) */
void hp_counter_tick(void)
{
    uint16_t now;
    now = TMR1L;
    now |= (uint16_t)TMR1H << 8;
    count0 += (uint16_t)(now - last0);
    last0 = now;
}

int32_t hal_counter_read(uint8_t channel)
{
    int32_t v;
    if (channel >= COUNTERS)
        return 0;
    INTCONbits.GIEL = 0;
#if HAL_PIC_SERVOS == 0
    v = channel == 0 ? count0 : channel == 1 ? count1 : count2;
#elif HAL_PIC_SERVOS <= 2
    v = channel == 0 ? count0 : count1;
#else
    v = count0;
#endif
    INTCONbits.GIEL = 1;
    return v;
}
