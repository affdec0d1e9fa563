/* strbuf.h: fixed log-line buffer. */
#include "strbuf.h"

void sb_reset(strbuf *sb)
{
    sb->len = 0;
    sb->buf[0] = '\0';
}

void sb_char(strbuf *sb, char c)
{
    if (sb->len + 1u < SB_CAP) {
        sb->buf[sb->len] = c;
        sb->len++;
        sb->buf[sb->len] = '\0';
    }
}

void sb_str(strbuf *sb, const char *s)
{
    while (*s != '\0')
        sb_char(sb, *s++);
}

void sb_int(strbuf *sb, int32_t v)
{
    char tmp[10];
    uint8_t n = 0;
    uint32_t mag;
    if (v < 0) {
        sb_char(sb, '-');
        mag = (uint32_t)0 - (uint32_t)v;
    } else {
        mag = (uint32_t)v;
    }
    do {
        tmp[n++] = (char)('0' + (char)(mag % 10UL));
        mag /= 10UL;
    } while (mag != 0UL);
    while (n > 0)
        sb_char(sb, tmp[--n]);
}

void sb_hex8(strbuf *sb, uint8_t v)
{
    static const char digits[] = "0123456789abcdef";
    sb_str(sb, "0x");
    sb_char(sb, digits[v >> 4]);
    sb_char(sb, digits[v & 0x0Fu]);
}
