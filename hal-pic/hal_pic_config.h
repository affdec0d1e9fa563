/* hal-pic: the PIC18F2550's configuration words (README.md: clock).
 *
 * The build force-includes this file (sdcc -Wp-include,...) into the
 * translation unit that holds main(), and only there: SDCC checks for
 * XINST=OFF where main() is, and the words must be set exactly once. The
 * firmware sources themselves stay free of target code. */
#ifndef HAL_PIC_CONFIG_H
#define HAL_PIC_CONFIG_H

/* 20 MHz crystal in HS mode, no PLL (PLLDIV/USBDIV unused), no USB regulator,
 * no watchdog, MCLR on, RB4:0 digital at reset, LVP off (RB5 is I/O),
 * XINST off (SDCC's code needs the legacy instruction set) */
#pragma config PLLDIV = 5, CPUDIV = OSC1_PLL2, USBDIV = 1
#pragma config FOSC = HS, FCMEN = OFF, IESO = OFF
#pragma config PWRT = ON, BOR = ON, BORV = 3, VREGEN = OFF
#pragma config WDT = OFF, WDTPS = 32768
#pragma config CCP2MX = ON, PBADEN = OFF, LPT1OSC = OFF, MCLRE = ON
#pragma config STVREN = ON, LVP = OFF, XINST = OFF, DEBUG = OFF
#pragma config CP0 = OFF, CP1 = OFF, CP2 = OFF, CP3 = OFF, CPB = OFF, CPD = OFF
#pragma config WRT0 = OFF, WRT1 = OFF, WRT2 = OFF, WRT3 = OFF, WRTC = OFF, WRTB = OFF, WRTD = OFF
#pragma config EBTR0 = OFF, EBTR1 = OFF, EBTR2 = OFF, EBTR3 = OFF, EBTRB = OFF

#endif
