/* hal-pic: log lines on the UART, TX = RC6, 115200 baud 8N1 (BRG16, BRGH,
 * SPBRG = 42: 116279 baud, +0.9 %), each line ended by CR LF. Blocking (about
 * 87 us per character). Built with HAL_PIC_LOG_UART=0 the lines are dropped. */
#include "hal_log.h"

#include "hal_pic.h"

void hp_log_init(void)
{
#if HAL_PIC_LOG_UART
    TRISCbits.TRISC6 = 0;
    TRISCbits.TRISC7 = 1;
    BAUDCON = 0x08; /* BRG16 */
    SPBRGH = 0;
    SPBRG = 42;
    TXSTA = 0x24;   /* TXEN, BRGH, asynchronous */
    RCSTA = 0x80;   /* SPEN (receiver off) */
#endif
}

#if HAL_PIC_LOG_UART
static void put_char(char c)
{
    while (!PIR1bits.TXIF)
        ;
    TXREG = (uint8_t)c;
}

/* write up to max characters of s, return how many */
static uint8_t put_str(const char *s, uint8_t max)
{
    uint8_t n = 0;
    if (s == 0)
        return 0;
    while (n < max && s[n] != '\0')
        put_char(s[n++]);
    return n;
}
#endif

void hal_log(const char *line)
{
#if HAL_PIC_LOG_UART
    (void)put_str(line, HAL_LOG_LINE_MAX);
    put_char('\r');
    put_char('\n');
#else
    (void)line;
#endif
}

void hal_log_int(const char *prefix, int32_t value)
{
#if HAL_PIC_LOG_UART
    char digits[10];
    uint8_t k = 0, n;
    uint32_t mag;

    n = put_str(prefix, HAL_LOG_LINE_MAX - HAL_LOG_INT_CHARS_MAX); /* keep room for the number */
    (void)n;
    if (value < 0) {
        put_char('-');
        mag = (uint32_t)0 - (uint32_t)value;
    } else {
        mag = (uint32_t)value;
    }
    do {
        digits[k++] = (char)('0' + (char)(mag % 10u));
        mag /= 10u;
    } while (mag != 0);
    while (k > 0)
        put_char(digits[--k]);
    put_char('\r');
    put_char('\n');
#else
    (void)prefix;
    (void)value;
#endif
}
