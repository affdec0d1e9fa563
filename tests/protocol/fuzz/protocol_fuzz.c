/* libFuzzer target for the chainsim wire protocol.
 *
 * The input is tried two ways:
 *   1. as a bare body: cs_decode(data, size);
 *   2. as a frame: cs_body_length on the first 4 bytes, then cs_decode on a
 *      heap copy of exactly body_len bytes (when that many follow).
 * Both decode from a buffer that ends exactly where the body ends, so
 * AddressSanitizer catches any read past `len`. Every accepted body is
 * re-encoded and must give back the identical frame, otherwise abort().
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "chainsim_protocol.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_reencode(const uint8_t *body, size_t len)
{
    static uint8_t frame[4u + CS_BODY_MAX];
    cs_msg m;
    const char *reason = 0;
    size_t n;

    if (cs_decode(body, len, &m, &reason) != CS_OK) {
        if (!reason || !reason[0])
            abort(); /* every rejection has a reason */
        return;
    }
    if (len < 2u || len > CS_BODY_MAX)
        abort(); /* accepted a body the length prefix would refuse */
    n = cs_encode(&m, frame, sizeof frame, &reason);
    if (n != 4u + len)
        abort(); /* refused, or different length */
    if (frame[0] != (uint8_t)len || frame[1] != (uint8_t)(len >> 8) || frame[2] != 0u ||
        frame[3] != 0u)
        abort();
    if (memcmp(frame + 4, body, len) != 0)
        abort(); /* not canonical */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint32_t body_len = 0;
    const char *reason = 0;

    /* 1: the whole input is a body */
    check_reencode(data, size);

    /* 2: the input is a length-prefixed frame */
    if (size >= 4u) {
        if (cs_body_length(data, &body_len, &reason) == CS_OK) {
            if (body_len < 2u || body_len > CS_BODY_MAX)
                abort();
            if (body_len <= size - 4u) {
                uint8_t *copy = (uint8_t *)malloc(body_len);
                if (!copy)
                    return 0;
                memcpy(copy, data + 4, body_len);
                check_reencode(copy, body_len);
                free(copy);
            }
        } else if (!reason || !reason[0]) {
            abort();
        }
    }
    return 0;
}
