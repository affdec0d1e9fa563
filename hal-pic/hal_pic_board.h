/* The PIC18F2550 module board: which pin carries what (hal-pic/README.md,
 * "Pin map"). Plain C definitions shared by three readers, so that they
 * cannot disagree: hal-pic (SDCC), the simulator's PIC module process
 * (tools/pic-module/, which drives and reads these pins in gpsim) and the
 * scene check (`chainsim run --check` with `target: pic`, which refuses a
 * module type whose sensors need channels the board does not have).
 *
 * Pins are numbered as on the 28-pin package (SPDIP/SOIC). */
#ifndef HAL_PIC_BOARD_H
#define HAL_PIC_BOARD_H

/* ---- clock ---------------------------------------------------------------- */
#define HP_BOARD_FOSC_HZ 20000000UL /* 20 MHz crystal, HS mode, no PLL */
#define HP_BOARD_FCY_HZ 5000000UL   /* instruction cycles per second (Fosc / 4) */

/* ---- servos --------------------------------------------------------------- */
/* servo i's pulse on RB(2 + i), pins 23..26; its potentiometer on AN i */
#define HP_BOARD_SERVOS_MAX 4u
#define HP_BOARD_SERVO_PULSE_PIN(i) (23u + (i))
/* pulse width in instruction cycles (0.2 us) = CENTER + cdeg * 5 / 18,
 * truncated toward zero; -9000..9000 cdeg = 1.0..2.0 ms */
#define HP_BOARD_SERVO_CENTER_CYCLES 7500
#define HP_BOARD_SERVO_CDEG_RANGE 9000
/* the potentiometer's wiper: linear from MIN counts (-90 deg) to MAX (+90) */
#define HP_BOARD_POT_MIN_COUNTS 102
#define HP_BOARD_POT_MAX_COUNTS 921

/* ---- analog inputs -------------------------------------------------------- */
/* AN0..AN4 (RA0, RA1, RA2, RA3, RA5): the servos' potentiometers take the
 * first ones, hal_adc_read(k) reads AN(servos + k), so a module with s servos
 * has 5 - s ADC channels. (AN8..AN12 sit on port B, taken by I2C and the
 * servo pulses.) Vref = Vdd = 5 V, 10 bits. */
#define HP_BOARD_ANALOG_INPUTS 5u
#define HP_BOARD_AN_PIN(n) ((n) < 4u ? (n) + 2u : 7u)
#define HP_BOARD_ADC_CHANNELS(servos) (HP_BOARD_ANALOG_INPUTS - (servos))

/* ---- digital inputs (touch sensors) ---------------------------------------- */
/* hal_gpio_read(0..3) = RB6, RB7, RC5, RC2 */
#define HP_BOARD_DIGITAL_INPUTS 4u
#define HP_BOARD_DIGITAL_PIN(i) ((i) == 0u ? 27u : (i) == 1u ? 28u : (i) == 2u ? 16u : 13u)

/* ---- encoder counters ------------------------------------------------------ */
/* channel 0 = Timer1 on T13CKI (RC0, pin 11); on a board with at most 2
 * servos channel 1 = RB4 (pin 25, interrupt on change), and without servos
 * channel 2 = INT2 on RB2 (pin 23). Rising edges, no direction. */
#define HP_BOARD_COUNTERS(servos) ((servos) == 0u ? 3u : (servos) <= 2u ? 2u : 1u)
#define HP_BOARD_COUNTER_PIN(i) ((i) == 0u ? 11u : (i) == 1u ? 25u : 23u)

/* ---- synchronism lines, UART, I2C ----------------------------------------- */
#define HP_BOARD_SIN_PIN 15u  /* RC4, input only while USB is off */
#define HP_BOARD_SOUT_PIN 12u /* RC1 */
#define HP_BOARD_TX_PIN 17u   /* RC6: log lines, 8N1 */
#define HP_BOARD_BAUD 115200UL
#define HP_BOARD_SDA_PIN 21u  /* RB0, open drain, external pull-up */
#define HP_BOARD_SCL_PIN 22u  /* RB1 */

/* ---- parameters in the data EEPROM ----------------------------------------- */
/* A module's parameter values (hal_param) are written to its data EEPROM,
 * as a programmer would write them for each unit:
 *     [0] HP_BOARD_PARAMS_MAGIC, [1] n (at most HP_BOARD_PARAMS_MAX), then n
 *     entries of 5 bytes: the parameter's index in hal_param_table, its
 *     value as int32, least significant byte first.
 * A blank EEPROM (0xFF) gives every parameter its default. */
#define HP_BOARD_PARAMS_MAGIC 0xC5u
#define HP_BOARD_PARAMS_MAX 16u
#define HP_BOARD_PARAMS_ENTRY_BYTES 5u

#endif
