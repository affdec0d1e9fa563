/* A fixed log-line buffer for firmware (no printf): append text, decimal
 * and hex, then hal_log(sb.buf). Truncates at SB_CAP-1 characters. */
#ifndef STRBUF_H
#define STRBUF_H

#include <stdint.h>

#include "hal_log.h"

#define SB_CAP (HAL_LOG_LINE_MAX + 1u) /* a HAL log line and its NUL */

typedef struct {
    char buf[SB_CAP];
    uint8_t len;
} strbuf;

void sb_reset(strbuf *sb);
void sb_char(strbuf *sb, char c);
void sb_str(strbuf *sb, const char *s);
void sb_int(strbuf *sb, int32_t v);
void sb_hex8(strbuf *sb, uint8_t v); /* "0x2a" */

#endif
