/* hal-pic: start-up, the 1 ms tick and the waits (configuration words:
 * hal_pic_config.h).
 *
 * Timer2 makes the tick: Fcy 5 MHz / prescale 4 / (PR2 + 1 = 250) / postscale 5
 * = 1 kHz, a low-priority interrupt. The tick counts hal_millis(), samples
 * Sin and extends the encoder counters. Outputs written between two waits
 * (servo set-points, Sout, queued I2C frames) are applied at the start of the
 * next wait, as in hal-sim. The waits poll the tick (the CPU stays awake; the
 * servo and I2C interrupts keep running). */
#include "hal_time.h"

#include "hal_pic.h"

volatile uint32_t hp_millis;
volatile uint8_t hp_sin_level;
static volatile uint8_t hp_ticks; /* low byte of the tick count, for the waits */

/* low-priority interrupt: the tick (Timer2) and the MSSP (I2C slave) */
void hp_isr_low(void) __interrupt(2)
{
    /* slave mode only: while hp_i2c_flush sends as master it turns SSPIE off
     * and polls SSPIF itself; a tick falling just after a byte must not take
     * that flag (the send then timed out and was repeated 50 ms later) */
    if (PIE1bits.SSPIE && PIR1bits.SSPIF)
        hp_i2c_isr();
    hp_counter_isr();
    if (PIR1bits.TMR2IF) {
        PIR1bits.TMR2IF = 0;
        hp_millis++;
        hp_ticks++;
        hp_sin_level = PORTCbits.RC4;
        hp_counter_tick();
    }
}

void hal_init(void)
{
    static uint8_t done;
    if (done)
        return;
    done = 1;

    INTCON = 0;
    RCONbits.IPEN = 1; /* two interrupt priorities */

    /* USB off so that RC4/RC5 are digital inputs */
    UCON = 0;
    UCFG = 0x08; /* UTRDIS */
    CMCON = 0x07; /* comparators off */

    hp_gpio_init();
    hp_adc_init();
    hp_sync_init();
    hp_counter_init();
    hp_log_init();
    hp_servo_init();
    hp_i2c_init();

    /* Timer2: 1 ms period, low priority */
    TMR2 = 0;
    PR2 = 249;
    T2CON = 0x25; /* postscale 1:5 (0100), TMR2ON, prescale 1:4 */
    IPR1bits.TMR2IP = 0;
    PIR1bits.TMR2IF = 0;
    PIE1bits.TMR2IE = 1;

    hp_sin_level = PORTCbits.RC4;
    INTCONbits.GIEH = 1;
    INTCONbits.GIEL = 1;
}

void hp_flush_outputs(void)
{
    hp_i2c_flush();
    hp_servo_flush();
    hp_sync_flush();
}

/* return at the next tick */
static void next_tick(void)
{
    uint8_t t = hp_ticks;
    while (hp_ticks == t)
        ;
}

void hal_tick_wait(void)
{
    hp_flush_outputs();
    next_tick();
}

void hal_delay_ms(uint16_t ms)
{
    hp_flush_outputs();
    if (ms == 0)
        ms = 1; /* every wait lasts at least one tick, as in hal-sim */
    while (ms != 0) {
        next_tick();
        ms--;
    }
}

uint8_t hal_wait_event_ms(uint16_t timeout_ms, uint8_t mask)
{
    uint8_t sin_before, happened;

    hp_flush_outputs();
    mask &= (uint8_t)(HAL_EV_I2C | HAL_EV_SIN_EDGE);
    if ((mask & HAL_EV_I2C) && hp_i2c_frame_waiting())
        return HAL_EV_I2C; /* a frame is already waiting: no need to sleep */
    if (timeout_ms == 0)
        timeout_ms = 1;
    sin_before = hp_sin_level;
    for (;;) {
        next_tick();
        happened = 0;
        if ((mask & HAL_EV_I2C) && hp_i2c_frame_waiting())
            happened |= HAL_EV_I2C;
        if ((mask & HAL_EV_SIN_EDGE) && hp_sin_level != sin_before)
            happened |= HAL_EV_SIN_EDGE;
        if (happened)
            return happened;
        if (--timeout_ms == 0)
            return 0;
    }
}

uint32_t hal_millis(void)
{
    uint32_t t;
    INTCONbits.GIEL = 0; /* the tick writes it: read the 4 bytes in one piece */
    t = hp_millis;
    INTCONbits.GIEL = 1;
    return t;
}
