/** @file
 * A fixed log-line buffer for firmware (no printf): append text, decimal
 * and hex, then hal_log(sb.buf). Truncates at SB_CAP-1 characters. */
#ifndef STRBUF_H
#define STRBUF_H

#include <stdint.h>

#include "hal_log.h"

#define SB_CAP (HAL_LOG_LINE_MAX + 1u) /**< a HAL log line and its NUL */

/** a line being built: always NUL-terminated */
typedef struct {
    char buf[SB_CAP]; /**< the text, NUL-terminated */
    uint8_t len;      /**< characters in buf, at most SB_CAP - 1 */
} strbuf;

/** empty the line */
void sb_reset(strbuf *sb);
/** append one character (dropped when the line is full) */
void sb_char(strbuf *sb, char c);
/** append a NUL-terminated text, cut where the line is full */
void sb_str(strbuf *sb, const char *s);
/** append v in decimal, with a '-' when negative */
void sb_int(strbuf *sb, int32_t v);
/** append v as "0x2a" */
void sb_hex8(strbuf *sb, uint8_t v);

#endif
