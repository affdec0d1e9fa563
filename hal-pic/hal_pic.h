/* hal-pic internals: the PIC18F2550 board (pin map and clock: README.md).
 * Only hal-pic's own files include this; firmware sees just the HAL headers. */
#ifndef HAL_PIC_H
#define HAL_PIC_H

#include <stdint.h>

#include <pic18f2550.h> /* generated from gputils' p18f2550.inc (tools/pic-devhdr.py) */

#include "hal_pic_board.h"
#include "hal_servo.h"

/* 20 MHz crystal, HS mode, no PLL: Fosc = 20 MHz, one instruction cycle
 * (Fosc/4) = 0.2 us */
#define HP_FOSC_HZ HP_BOARD_FOSC_HZ
#define HP_FCY_HZ HP_BOARD_FCY_HZ

/* servo outputs present on this build of the board (RB2.. in order, at most 4) */
#ifndef HAL_PIC_SERVOS
#define HAL_PIC_SERVOS 2
#endif
#if HAL_PIC_SERVOS > HAL_SERVOS_MAX
#error "hal-pic drives at most HAL_SERVOS_MAX (4) servos (RB2..RB5)"
#endif

/* I2C receive ring in bytes (a power of two, at most 256): frames are stored
 * as len, to_addr7, data... */
#ifndef HAL_PIC_I2C_RX_RING
#define HAL_PIC_I2C_RX_RING 128u
#endif
/* I2C transmit queue in bytes (frames as addr7, len, data...): one full frame */
#ifndef HAL_PIC_I2C_TX_BUF
#define HAL_PIC_I2C_TX_BUF 40u
#endif

/* 1 = hal_log writes lines to the UART (RC6/TX, 115200 8N1), 0 = drops them */
#ifndef HAL_PIC_LOG_UART
#define HAL_PIC_LOG_UART 1
#endif

/* ---- shared between the hal-pic files ----------------------------------- */

/* time base (hal_time.c): incremented by the 1 ms Timer2 interrupt */
extern volatile uint32_t hp_millis;
extern volatile uint8_t hp_sin_level; /* Sin as sampled at the last tick */

/* flush the outputs written since the last wait (queued I2C frames, servo
 * set-points, Sout); called at the start of every wait */
void hp_flush_outputs(void);

/* set-up and interrupt work of each peripheral; the interrupt vectors are
 * hp_isr_high (hal_servo.c: only the servo pulses, CCP1 on Timer3) and
 * hp_isr_low (hal_time.c: the tick, then hp_i2c_isr and hp_counter_tick) */
void hp_servo_init(void);
void hp_servo_flush(void);
void hp_i2c_init(void);
void hp_i2c_isr(void);    /* low priority: MSSP */
void hp_i2c_flush(void);
uint8_t hp_i2c_frame_waiting(void);
void hp_sync_init(void);
void hp_sync_flush(void);
void hp_adc_init(void);
uint16_t hp_adc_convert(uint8_t an); /* one conversion of AN<an>, counts */
void hp_gpio_init(void);
void hp_counter_init(void);
void hp_counter_tick(void); /* low priority, every 1 ms */
void hp_counter_isr(void);  /* low priority: the INT2 counter of a board without servos */
void hp_log_init(void);

#endif
