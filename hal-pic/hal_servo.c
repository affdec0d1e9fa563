/* hal-pic: servo pulses and the servos' potentiometers.
 *
 * Pulses: Timer3 runs free at Fcy = 5 MHz (0.2 us per count) and clocks CCP1
 * in compare mode ("software interrupt on match", the CCP1 pin is not used).
 * The 20 ms frame (50 Hz) is 8 slots of 2.5 ms (12500 counts); servo i gets
 * slot i: its pin (RB2 + i) goes high at the slot start and low after its
 * pulse width. The high-priority interrupt sets each compare relative to the
 * previous scheduled edge, never to "now", so the latency cancels out: the
 * width is exact to the instruction cycle (0.2 us; one edge in 41 s one
 * count late, below) and the frame is exactly 20 ms.
 *
 * Set-point mapping (centidegrees -> pulse):
 *     width_us = 1500 + cdeg / 18          (-9000 -> 1000 us, 0 -> 1500, 9000 -> 2000)
 *     counts   = 7500 + cdeg * 5 / 18      (Timer3 counts of 0.2 us, truncated toward 0)
 * The servo turns -90..+90 degrees; set-points beyond that (up to the HAL's
 * +/-HAL_SERVO_CDEG_MAX) are clamped to 1.0 / 2.0 ms. Beyond: HAL_ERR_ARG.
 *
 * Measured angle: the servo's potentiometer wiper on AN<servo> (RA0, RA1, ..),
 * linear between HP_BOARD_POT_MIN_COUNTS (-90 deg) and HP_BOARD_POT_MAX_COUNTS
 * (+90 deg) (hal_pic_board.h); calibrate these for the servo model used. */
#include "hal_servo.h"

#include "hal_pic.h"

#define SERVO_CDEG_RANGE HP_BOARD_SERVO_CDEG_RANGE          /* the servo's range (+/-) */
#define SERVO_CENTER_COUNTS ((uint16_t)HP_BOARD_SERVO_CENTER_CYCLES) /* 1.5 ms */
#define SLOT_COUNTS 12500u         /* 2.5 ms: 8 slots = one 20 ms frame */
#define SLOTS 8u
#define SERVO_PINS_MASK 0x3Cu      /* RB2..RB5 */
/* the pins of this build's servos: only those are outputs (a board with
 * fewer servos counts encoder pulses on RB2 and RB4, hal_counter.c) */
#define SERVO_OUTPUTS_MASK ((uint8_t)(((1u << HAL_PIC_SERVOS) - 1u) << 2))
#define SERVO_POT_MIN_COUNTS HP_BOARD_POT_MIN_COUNTS /* ~0.5 V at -90 deg */
#define SERVO_POT_MAX_COUNTS HP_BOARD_POT_MAX_COUNTS /* ~4.5 V at +90 deg */

#if HAL_PIC_SERVOS > 0
/* widths in Timer3 counts: pending (written by setspangle), active (read by
 * the interrupt); 0 = no pulses */
static uint16_t pending_width[HAL_PIC_SERVOS];
static volatile uint16_t active_width[HAL_PIC_SERVOS];
#endif
static uint16_t edge;        /* Timer3 value of the scheduled compare */
static uint16_t slot_start;  /* Timer3 value of the current slot's start */
static uint16_t cur_width;   /* pulse width in the current slot */
static uint8_t slot;         /* 0..7 */
static uint8_t slot_bit;     /* LATB bit of slot's servo (0x04 << slot) */
static uint8_t next_pins;    /* servo pins to drive at the scheduled compare */

/* high-priority interrupt: only CCP1 uses it. The first statement drives the
 * pins precomputed for this compare, so rising and falling edges come the
 * same number of cycles after their match. No calls and no arithmetic
 * helpers here (they are not reentrant). */
void hp_isr_high(void) __interrupt(1)
{
    LATB = (uint8_t)((LATB & (uint8_t)~SERVO_PINS_MASK) | next_pins);
    if (!PIR1bits.CCP1IF)
        return;
    if (next_pins != 0) {
        /* the pulse of this slot just started: schedule its end */
        next_pins = 0;
        edge = slot_start + cur_width;
    } else {
        /* a pulse ended or an empty slot began: schedule the next slot */
        slot = (uint8_t)((slot + 1u) & (SLOTS - 1u));
        slot_bit = slot == 0 ? 0x04u : (uint8_t)(slot_bit << 1);
        slot_start += SLOT_COUNTS;
        edge = slot_start;
#if HAL_PIC_SERVOS > 0
        cur_width = 0;
        if (slot < HAL_PIC_SERVOS)
            cur_width = active_width[slot];
        if (cur_width != 0)
            next_pins = slot_bit;
#endif
    }
    /* gpsim 0.31 never matches a compare value of 0 (its Timer1/3 breaks
     * only at values above the timer's, and the rollover comes first), so an
     * edge scheduled at Timer3 = 0 stopped the pulses for good: slot 0's
     * falling edge of a servo at 0 deg gets there after 16.4 s, slot 7's
     * start after 41 s whatever the servos. The part matches at 0; one count
     * later does no harm there: that one edge 0.2 us late, the next slots
     * still counted from slot_start */
    if (edge == 0)
        edge = 1;
    /* High byte first: the half-written value (new high, old low) never
     * equals Timer3 before the low byte follows. Then the high byte once
     * more, and only then clear the flag: a PIC18 sees the same compare
     * value and no match in these few cycles (the next edge is >= 2499
     * counts away). gpsim 0.31 copies CCPR1L into CCPR1H at every Timer2
     * period match (its PWM duty-cycle latch, also in compare mode) and
     * takes the compare value from both registers at each write: a copy
     * between the two writes compared on (old low):(new low) and the edge
     * came one Timer3 wrap late (docs/pic-in-the-loop.md). The last write,
     * of the high byte, sets the whole value again; a match on the
     * half-written value inside the window is dropped with the flag. */
    CCPR1H = (uint8_t)(edge >> 8);
    CCPR1L = (uint8_t)edge;
    CCPR1H = (uint8_t)(edge >> 8);
    PIR1bits.CCP1IF = 0;
}

void hp_servo_init(void)
{
    LATB &= (uint8_t)~SERVO_PINS_MASK;
    TRISB &= (uint8_t)~SERVO_OUTPUTS_MASK; /* RB2.. of the servos it has: outputs */

    /* Timer3: internal clock Fcy, 1:1, 16-bit reads, clock source of both CCPs */
    T3CON = 0xC0; /* RD16 | T3CCP2, stopped */
    /* the first compare falls in (empty) slot 7, which began at Timer3 = 0:
     * frames then start at 12500, 112500, ... */
    slot = SLOTS - 1u;
    slot_bit = 0;
    slot_start = 0;
    cur_width = 0;
    next_pins = 0;
    edge = 100;
    CCPR1H = (uint8_t)(edge >> 8);
    CCPR1L = (uint8_t)edge;
    TMR3H = 0;
    TMR3L = 0;
    CCP1CON = 0x0A; /* compare, software interrupt on match */
    IPR1bits.CCP1IP = 1;
    PIR1bits.CCP1IF = 0;
    PIE1bits.CCP1IE = 1;
    T3CON = 0xC1; /* run */
}

void hp_servo_flush(void)
{
#if HAL_PIC_SERVOS > 0
    uint8_t i;
    for (i = 0; i < HAL_PIC_SERVOS; i++) {
        INTCONbits.GIEH = 0; /* the interrupt reads the 2-byte width: a few cycles */
        active_width[i] = pending_width[i];
        INTCONbits.GIEH = 1;
    }
#endif
}

hal_status setspangle(uint8_t servo, int16_t angle_cdeg)
{
#if HAL_PIC_SERVOS > 0
    int16_t a = angle_cdeg;
    if (servo >= HAL_PIC_SERVOS || a < -HAL_SERVO_CDEG_MAX || a > HAL_SERVO_CDEG_MAX)
        return HAL_ERR_ARG;
    if (a > SERVO_CDEG_RANGE)
        a = SERVO_CDEG_RANGE;
    if (a < -SERVO_CDEG_RANGE)
        a = -SERVO_CDEG_RANGE;
    pending_width[servo] = (uint16_t)((int16_t)SERVO_CENTER_COUNTS +
                                      (int16_t)(((int32_t)a * 5L) / 18L));
    return HAL_OK;
#else
    (void)servo;
    (void)angle_cdeg;
    return HAL_ERR_ARG;
#endif
}

hal_status hal_servo_release(uint8_t servo)
{
#if HAL_PIC_SERVOS > 0
    if (servo >= HAL_PIC_SERVOS)
        return HAL_ERR_ARG;
    pending_width[servo] = 0;
    return HAL_OK;
#else
    (void)servo;
    return HAL_ERR_ARG;
#endif
}

int16_t hal_servo_angle_cdeg(uint8_t servo)
{
#if HAL_PIC_SERVOS > 0
    int32_t c;
    if (servo >= HAL_PIC_SERVOS)
        return 0;
    c = (int32_t)hp_adc_convert(servo) - SERVO_POT_MIN_COUNTS;
    c = c * (2L * SERVO_CDEG_RANGE) / (SERVO_POT_MAX_COUNTS - SERVO_POT_MIN_COUNTS) -
        SERVO_CDEG_RANGE;
    return (int16_t)c;
#else
    (void)servo;
    return 0;
#endif
}

uint8_t hal_servo_count(void)
{
    return HAL_PIC_SERVOS;
}
