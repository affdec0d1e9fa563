/* chainsim wire protocol: encoder and decoder (see chainsim_protocol.h and
 * docs/protocol.md).
 *
 * Portable C99 for hosts and small compilers alike: no allocation, no stdio,
 * no variable-length arrays, no compiler extensions. Every field is written
 * and read byte by byte in little-endian order; structs are never copied to
 * or from the wire as a whole. The decoder never reads past `len`, checks
 * every count before using it as a loop bound, and accepts exactly the
 * bodies the encoder can produce, so decode followed by encode gives back
 * the same bytes.
 */
#include "chainsim_protocol.h"

#include <string.h> /* memset */

/* ------------------------------------------------------------------------ */
/* wire sizes and compile-time checks                                        */
/* ------------------------------------------------------------------------ */

#define CS_PREFIX_LEN 4u /* u32 body length */
#define CS_TYPE_LEN 2u   /* u16 message type */

/* largest encoded pieces */
#define CS_I2C_FRAME_WIRE_MAX (1u + 1u + CS_I2C_DATA_MAX) /* addr, len, data */
#define CS_NAME_WIRE_MAX(bufsize) (1u + ((bufsize) - 1u)) /* u8 len + chars */

/* largest legal body of each message type, type field included */
#define CS_HELLO_BODY_MAX                                                    \
    (CS_TYPE_LEN + 4u + 2u + 2u + 4u + CS_NAME_WIRE_MAX(CS_TYPE_NAME_MAX))
#define CS_WELCOME_BODY_MAX                                                  \
    (CS_TYPE_LEN + 2u + 2u + 4u + 8u + 1u +                                  \
     CS_PARAMS_MAX * (CS_NAME_WIRE_MAX(CS_PARAM_NAME_MAX) + 4u))
#define CS_REASON_BODY_MAX (CS_TYPE_LEN + CS_NAME_WIRE_MAX(CS_REASON_MAX))
#define CS_TICK_BEGIN_BODY_MAX                                               \
    (CS_TYPE_LEN + 8u + 1u + 1u + 2u + 2u + 1u + 4u * CS_SERVOS_MAX + 1u +   \
     2u * CS_ADC_MAX + 1u + 4u * CS_COUNTERS_MAX + 1u +                      \
     CS_I2C_FRAMES_MAX * CS_I2C_FRAME_WIRE_MAX)
#define CS_TICK_END_BODY_MAX                                                 \
    (CS_TYPE_LEN + 8u + 1u + 1u + 1u + 1u + 1u + 4u * CS_SERVOS_MAX + 1u +   \
     CS_I2C_FRAMES_MAX * CS_I2C_FRAME_WIRE_MAX + 1u +                        \
     CS_LOG_LINES_MAX * CS_NAME_WIRE_MAX(CS_LOG_LINE_MAX))

/* C99 has no _Static_assert: a negative array size stops the build. */
#define CS_STATIC_ASSERT(cond, name) typedef char cs_static_assert_##name[(cond) ? 1 : -1]

/* the largest legal message of every type fits in CS_BODY_MAX */
CS_STATIC_ASSERT(CS_HELLO_BODY_MAX <= CS_BODY_MAX, hello_fits);
CS_STATIC_ASSERT(CS_WELCOME_BODY_MAX <= CS_BODY_MAX, welcome_fits);
CS_STATIC_ASSERT(CS_REASON_BODY_MAX <= CS_BODY_MAX, reason_fits);
CS_STATIC_ASSERT(CS_TICK_BEGIN_BODY_MAX <= CS_BODY_MAX, tick_begin_fits);
CS_STATIC_ASSERT(CS_TICK_END_BODY_MAX <= CS_BODY_MAX, tick_end_fits);
/* counts and string lengths travel as u8 */
CS_STATIC_ASSERT(CS_SERVOS_MAX <= 8u, servo_enable_is_u8); /* one bit per servo */
CS_STATIC_ASSERT(CS_ADC_MAX <= 255u && CS_COUNTERS_MAX <= 255u, counts_u8);
CS_STATIC_ASSERT(CS_I2C_FRAMES_MAX <= 255u && CS_I2C_DATA_MAX <= 255u, i2c_u8);
CS_STATIC_ASSERT(CS_LOG_LINES_MAX <= 255u && CS_PARAMS_MAX <= 255u, lines_u8);
CS_STATIC_ASSERT(CS_TYPE_NAME_MAX <= 256u && CS_PARAM_NAME_MAX <= 256u, names_u8);
CS_STATIC_ASSERT(CS_LOG_LINE_MAX <= 256u && CS_REASON_MAX <= 256u, texts_u8);
CS_STATIC_ASSERT(CS_TYPE_NAME_MAX >= 2u && CS_PARAM_NAME_MAX >= 2u, names_fit_one_char);

/* ------------------------------------------------------------------------ */
/* reasons                                                                   */
/* ------------------------------------------------------------------------ */

static const char R_NULL_ARG[] = "null argument";
static const char R_UNKNOWN_TYPE[] = "unknown message type";
static const char R_TRUNCATED[] = "truncated body";
static const char R_NO_TYPE[] = "truncated body: shorter than the message type field";
static const char R_TRAILING[] = "trailing bytes after the message";
static const char R_BODY_TOO_LONG[] = "body length over CS_BODY_MAX";
static const char R_BODY_ZERO[] = "body length is 0";
static const char R_CAP[] = "output buffer too small for the frame";

static const char R_MAGIC[] = "HELLO magic is not CS_MAGIC";
static const char R_HELLO_VERSION[] = "HELLO version is not CS_VERSION";
static const char R_WELCOME_VERSION[] = "WELCOME version is not CS_VERSION";
static const char R_N_PARAMS[] = "n_params over CS_PARAMS_MAX";
static const char R_WAKE_REASON[] = "wake_reason has bits outside CS_WAKE_ALL";
static const char R_SIN_LEVEL[] = "sin_level is not 0 or 1";
static const char R_SOUT_LEVEL[] = "sout_level is not 0 or 1";
static const char R_N_SERVOS[] = "n_servos over CS_SERVOS_MAX";
static const char R_N_ADC[] = "n_adc over CS_ADC_MAX";
static const char R_ADC_VALUE[] = "adc value over CS_ADC_COUNTS_MAX";
static const char R_N_COUNTERS[] = "n_counters over CS_COUNTERS_MAX";
static const char R_N_I2C[] = "n_i2c over CS_I2C_FRAMES_MAX";
static const char R_I2C_ADDR[] = "i2c frame addr over 127";
static const char R_I2C_LEN_ZERO[] = "i2c frame len is 0";
static const char R_I2C_LEN_MAX[] = "i2c frame len over CS_I2C_DATA_MAX";
static const char R_WAKE_EVENTS[] =
    "wake_events has bits other than CS_WAKE_I2C|CS_WAKE_SIN_EDGE";
static const char R_OWN_ADDR[] = "i2c_address over 127";
static const char R_SERVO_ENABLE[] = "servo_enable has bits at or beyond n_servos";
static const char R_N_LOG[] = "n_log over CS_LOG_LINES_MAX";

/* how one string field is checked */
typedef struct {
    unsigned char is_name;  /* names: non-empty, no control characters */
    const char *too_long;   /* wire length >= buffer size */
    const char *unterminated; /* encoder: no NUL inside the buffer */
    const char *empty;      /* names only */
    const char *bad_char;   /* names: control char; texts: NUL */
} cs_text_rule;

static const cs_text_rule RULE_TYPE_NAME = {
    1u, "HELLO type name too long", "HELLO type name not NUL-terminated",
    "HELLO type name is empty", "HELLO type name contains a control character"};
static const cs_text_rule RULE_PARAM_NAME = {
    1u, "param name too long", "param name not NUL-terminated",
    "param name is empty", "param name contains a control character"};
static const cs_text_rule RULE_LOG_LINE = {
    0u, "log line too long", "log line not NUL-terminated", 0,
    "log line contains a NUL byte"};
static const cs_text_rule RULE_REASON = {
    0u, "reason too long", "reason not NUL-terminated", 0,
    "reason contains a NUL byte"};

/* NULL if the n characters s[0..n) are acceptable for the rule */
static const char *check_text(const unsigned char *s, size_t n, const cs_text_rule *rule)
{
    size_t i;
    if (rule->is_name && n == 0u)
        return rule->empty;
    for (i = 0u; i < n; i++) {
        if (rule->is_name ? (s[i] < 0x20u || s[i] == 0x7Fu) : (s[i] == 0u))
            return rule->bad_char;
    }
    return 0;
}

static const char *check_i2c_frame(const cs_i2c_frame *f)
{
    if (f->addr > 127u)
        return R_I2C_ADDR;
    if (f->len == 0u)
        return R_I2C_LEN_ZERO;
    if (f->len > CS_I2C_DATA_MAX)
        return R_I2C_LEN_MAX;
    return 0;
}

/* ------------------------------------------------------------------------ */
/* encoder                                                                   */
/* ------------------------------------------------------------------------ */

typedef struct {
    uint8_t *buf;
    size_t cap;
    size_t pos;
    const char *err; /* first error wins */
} cs_writer;

static void w_fail(cs_writer *w, const char *reason)
{
    if (!w->err)
        w->err = reason;
}

static void w_u8(cs_writer *w, uint8_t v)
{
    if (w->err)
        return;
    if (w->pos >= w->cap) {
        w->err = R_CAP;
        return;
    }
    w->buf[w->pos] = v;
    w->pos++;
}

static void w_u16(cs_writer *w, uint16_t v)
{
    w_u8(w, (uint8_t)(v & 0xFFu));
    w_u8(w, (uint8_t)((v >> 8) & 0xFFu));
}

static void w_u32(cs_writer *w, uint32_t v)
{
    w_u8(w, (uint8_t)(v & 0xFFu));
    w_u8(w, (uint8_t)((v >> 8) & 0xFFu));
    w_u8(w, (uint8_t)((v >> 16) & 0xFFu));
    w_u8(w, (uint8_t)((v >> 24) & 0xFFu));
}

static void w_u64(cs_writer *w, uint64_t v)
{
    w_u32(w, (uint32_t)(v & 0xFFFFFFFFu));
    w_u32(w, (uint32_t)(v >> 32));
}

static void w_i32(cs_writer *w, int32_t v)
{
    w_u32(w, (uint32_t)v); /* conversion to unsigned is modulo 2^32: two's complement */
}

/* a NUL-terminated string held in a buffer of `size` bytes */
static void w_text(cs_writer *w, const char *s, size_t size, const cs_text_rule *rule)
{
    size_t n = 0u, i;
    const char *bad;
    if (w->err)
        return;
    while (n < size && s[n] != '\0')
        n++;
    if (n >= size) {
        w_fail(w, rule->unterminated);
        return;
    }
    bad = check_text((const unsigned char *)s, n, rule);
    if (bad) {
        w_fail(w, bad);
        return;
    }
    w_u8(w, (uint8_t)n);
    for (i = 0u; i < n; i++)
        w_u8(w, (uint8_t)(unsigned char)s[i]);
}

static void w_i2c_frames(cs_writer *w, uint8_t n, const cs_i2c_frame *frames)
{
    uint8_t i, j;
    if (n > CS_I2C_FRAMES_MAX) {
        w_fail(w, R_N_I2C);
        return;
    }
    w_u8(w, n);
    for (i = 0u; i < n && !w->err; i++) {
        const cs_i2c_frame *f = &frames[i];
        const char *bad = check_i2c_frame(f);
        if (bad) {
            w_fail(w, bad);
            return;
        }
        w_u8(w, f->addr);
        w_u8(w, f->len);
        for (j = 0u; j < f->len; j++)
            w_u8(w, f->data[j]);
    }
}

static void enc_hello(cs_writer *w, const cs_hello *h)
{
    if (h->magic != CS_MAGIC) {
        w_fail(w, R_MAGIC);
        return;
    }
    if (h->version != CS_VERSION) {
        w_fail(w, R_HELLO_VERSION);
        return;
    }
    w_u32(w, h->magic);
    w_u16(w, h->version);
    w_u16(w, h->module_index);
    w_u32(w, h->pid);
    w_text(w, h->type, sizeof h->type, &RULE_TYPE_NAME);
}

static void enc_welcome(cs_writer *w, const cs_welcome *m)
{
    uint8_t i;
    if (m->version != CS_VERSION) {
        w_fail(w, R_WELCOME_VERSION);
        return;
    }
    if (m->n_params > CS_PARAMS_MAX) {
        w_fail(w, R_N_PARAMS);
        return;
    }
    w_u16(w, m->version);
    w_u16(w, m->module_index);
    w_u32(w, m->tick_us);
    w_u64(w, m->seed);
    w_u8(w, m->n_params);
    for (i = 0u; i < m->n_params; i++) {
        w_text(w, m->params[i].name, sizeof m->params[i].name, &RULE_PARAM_NAME);
        w_i32(w, m->params[i].value);
    }
}

static void enc_reason(cs_writer *w, const cs_reason *m)
{
    w_text(w, m->reason, sizeof m->reason, &RULE_REASON);
}

static void enc_tick_begin(cs_writer *w, const cs_tick_begin *t)
{
    uint8_t i;
    if ((t->wake_reason & ~CS_WAKE_ALL) != 0u) {
        w_fail(w, R_WAKE_REASON);
        return;
    }
    if (t->sin_level > 1u) {
        w_fail(w, R_SIN_LEVEL);
        return;
    }
    if (t->n_servos > CS_SERVOS_MAX) {
        w_fail(w, R_N_SERVOS);
        return;
    }
    if (t->n_adc > CS_ADC_MAX) {
        w_fail(w, R_N_ADC);
        return;
    }
    if (t->n_counters > CS_COUNTERS_MAX) {
        w_fail(w, R_N_COUNTERS);
        return;
    }
    for (i = 0u; i < t->n_adc; i++) {
        if (t->adc[i] > CS_ADC_COUNTS_MAX) {
            w_fail(w, R_ADC_VALUE);
            return;
        }
    }
    w_u64(w, t->time_us);
    w_u8(w, t->wake_reason);
    w_u8(w, t->sin_level);
    w_u16(w, t->digital_in);
    w_u16(w, t->i2c_tx_queued);
    w_u8(w, t->n_servos);
    for (i = 0u; i < t->n_servos; i++)
        w_i32(w, t->servo_pos[i]);
    w_u8(w, t->n_adc);
    for (i = 0u; i < t->n_adc; i++)
        w_u16(w, t->adc[i]);
    w_u8(w, t->n_counters);
    for (i = 0u; i < t->n_counters; i++)
        w_i32(w, t->counter[i]);
    w_i2c_frames(w, t->n_i2c, t->i2c);
}

static void enc_tick_end(cs_writer *w, const cs_tick_end *t)
{
    uint8_t i;
    if ((t->wake_events & ~(CS_WAKE_I2C | CS_WAKE_SIN_EDGE)) != 0u) {
        w_fail(w, R_WAKE_EVENTS);
        return;
    }
    if (t->sout_level > 1u) {
        w_fail(w, R_SOUT_LEVEL);
        return;
    }
    if (t->i2c_address > 127u) {
        w_fail(w, R_OWN_ADDR);
        return;
    }
    if (t->n_servos > CS_SERVOS_MAX) {
        w_fail(w, R_N_SERVOS);
        return;
    }
    if ((t->servo_enable >> t->n_servos) != 0u) {
        w_fail(w, R_SERVO_ENABLE);
        return;
    }
    if (t->n_log > CS_LOG_LINES_MAX) {
        w_fail(w, R_N_LOG);
        return;
    }
    w_u64(w, t->wake_time_us);
    w_u8(w, t->wake_events);
    w_u8(w, t->sout_level);
    w_u8(w, t->i2c_address);
    w_u8(w, t->n_servos);
    w_u8(w, t->servo_enable);
    for (i = 0u; i < t->n_servos; i++)
        w_i32(w, t->servo_setpoint[i]);
    w_i2c_frames(w, t->n_i2c, t->i2c);
    w_u8(w, t->n_log);
    for (i = 0u; i < t->n_log; i++)
        w_text(w, t->log[i], sizeof t->log[i], &RULE_LOG_LINE);
}

size_t cs_encode(const cs_msg *m, uint8_t *buf, size_t cap, const char **reason)
{
    cs_writer w;
    size_t body;
    if (!m || !buf) {
        if (reason)
            *reason = R_NULL_ARG;
        return 0u;
    }
    w.buf = buf;
    w.cap = cap;
    w.pos = 0u;
    w.err = 0;
    w_u32(&w, 0u); /* length placeholder, patched below */
    w_u16(&w, m->type);
    switch (m->type) {
    case CS_MSG_HELLO:
        enc_hello(&w, &m->u.hello);
        break;
    case CS_MSG_WELCOME:
        enc_welcome(&w, &m->u.welcome);
        break;
    case CS_MSG_REJECT:
        enc_reason(&w, &m->u.reject);
        break;
    case CS_MSG_TICK_BEGIN:
        enc_tick_begin(&w, &m->u.tick_begin);
        break;
    case CS_MSG_TICK_END:
        enc_tick_end(&w, &m->u.tick_end);
        break;
    case CS_MSG_SHUTDOWN:
        enc_reason(&w, &m->u.shutdown);
        break;
    default:
        w_fail(&w, R_UNKNOWN_TYPE);
        break;
    }
    if (!w.err && w.pos - CS_PREFIX_LEN > CS_BODY_MAX)
        w.err = R_BODY_TOO_LONG; /* cannot happen: see the static asserts */
    if (w.err) {
        if (reason)
            *reason = w.err;
        return 0u;
    }
    body = w.pos - CS_PREFIX_LEN;
    buf[0] = (uint8_t)(body & 0xFFu);
    buf[1] = (uint8_t)((body >> 8) & 0xFFu);
    buf[2] = (uint8_t)((body >> 16) & 0xFFu);
    buf[3] = (uint8_t)((body >> 24) & 0xFFu);
    return w.pos;
}

/* ------------------------------------------------------------------------ */
/* length prefix                                                             */
/* ------------------------------------------------------------------------ */

int cs_body_length(const uint8_t prefix[4], uint32_t *body_len, const char **reason)
{
    uint32_t n;
    const char *err = 0;
    if (!prefix || !body_len) {
        err = R_NULL_ARG;
    } else {
        n = (uint32_t)prefix[0] | ((uint32_t)prefix[1] << 8) | ((uint32_t)prefix[2] << 16) |
            ((uint32_t)prefix[3] << 24);
        if (n == 0u)
            err = R_BODY_ZERO;
        else if (n < CS_TYPE_LEN)
            err = R_NO_TYPE;
        else if (n > CS_BODY_MAX)
            err = R_BODY_TOO_LONG;
        else
            *body_len = n;
    }
    if (err) {
        if (reason)
            *reason = err;
        return CS_ERR;
    }
    return CS_OK;
}

/* ------------------------------------------------------------------------ */
/* decoder                                                                   */
/* ------------------------------------------------------------------------ */

typedef struct {
    const uint8_t *p;
    size_t len;
    size_t pos; /* invariant: pos <= len */
    const char *err; /* first error wins; reads after an error return 0 */
} cs_reader;

static void r_fail(cs_reader *r, const char *reason)
{
    if (!r->err)
        r->err = reason;
}

static uint8_t r_u8(cs_reader *r)
{
    uint8_t v;
    if (r->err)
        return 0u;
    if (r->pos >= r->len) {
        r->err = R_TRUNCATED;
        return 0u;
    }
    v = r->p[r->pos];
    r->pos++;
    return v;
}

static uint16_t r_u16(cs_reader *r)
{
    uint16_t lo = r_u8(r);
    uint16_t hi = r_u8(r);
    return (uint16_t)(lo | (uint16_t)(hi << 8));
}

static uint32_t r_u32(cs_reader *r)
{
    uint32_t b0 = r_u8(r);
    uint32_t b1 = r_u8(r);
    uint32_t b2 = r_u8(r);
    uint32_t b3 = r_u8(r);
    return b0 | (b1 << 8) | (b2 << 16) | (b3 << 24);
}

static uint64_t r_u64(cs_reader *r)
{
    uint64_t lo = r_u32(r);
    uint64_t hi = r_u32(r);
    return lo | (hi << 32);
}

static int32_t r_i32(cs_reader *r)
{
    uint32_t u = r_u32(r);
    /* portable two's complement without implementation-defined conversion */
    if (u <= 0x7FFFFFFFu)
        return (int32_t)u;
    return -(int32_t)(~u) - 1;
}

/* u8 length + chars into a buffer of `size` bytes, NUL-terminated */
static void r_text(cs_reader *r, char *dst, size_t size, const cs_text_rule *rule)
{
    size_t n, i;
    const char *bad;
    n = r_u8(r);
    if (r->err)
        return;
    if (n >= size) {
        r_fail(r, rule->too_long);
        return;
    }
    if (r->len - r->pos < n) {
        r_fail(r, R_TRUNCATED);
        return;
    }
    bad = check_text(r->p + r->pos, n, rule);
    if (bad) {
        r_fail(r, bad);
        return;
    }
    for (i = 0u; i < n; i++)
        dst[i] = (char)r->p[r->pos + i];
    dst[n] = '\0';
    r->pos += n;
}

static void r_i2c_frames(cs_reader *r, uint8_t *n_out, cs_i2c_frame *frames)
{
    uint8_t n, i, j;
    n = r_u8(r);
    if (r->err)
        return;
    if (n > CS_I2C_FRAMES_MAX) {
        r_fail(r, R_N_I2C);
        return;
    }
    *n_out = n;
    for (i = 0u; i < n; i++) {
        cs_i2c_frame *f = &frames[i];
        const char *bad;
        f->addr = r_u8(r);
        f->len = r_u8(r);
        if (r->err)
            return;
        bad = check_i2c_frame(f);
        if (bad) {
            r_fail(r, bad);
            return;
        }
        for (j = 0u; j < f->len; j++)
            f->data[j] = r_u8(r);
        if (r->err)
            return;
    }
}

static void dec_hello(cs_reader *r, cs_hello *h)
{
    h->magic = r_u32(r);
    if (!r->err && h->magic != CS_MAGIC) {
        r_fail(r, R_MAGIC);
        return;
    }
    h->version = r_u16(r);
    if (!r->err && h->version != CS_VERSION) {
        r_fail(r, R_HELLO_VERSION);
        return;
    }
    h->module_index = r_u16(r);
    h->pid = r_u32(r);
    r_text(r, h->type, sizeof h->type, &RULE_TYPE_NAME);
}

static void dec_welcome(cs_reader *r, cs_welcome *m)
{
    uint8_t i;
    m->version = r_u16(r);
    if (!r->err && m->version != CS_VERSION) {
        r_fail(r, R_WELCOME_VERSION);
        return;
    }
    m->module_index = r_u16(r);
    m->tick_us = r_u32(r);
    m->seed = r_u64(r);
    m->n_params = r_u8(r);
    if (r->err)
        return;
    if (m->n_params > CS_PARAMS_MAX) {
        r_fail(r, R_N_PARAMS);
        return;
    }
    for (i = 0u; i < m->n_params && !r->err; i++) {
        r_text(r, m->params[i].name, sizeof m->params[i].name, &RULE_PARAM_NAME);
        m->params[i].value = r_i32(r);
    }
}

static void dec_reason(cs_reader *r, cs_reason *m)
{
    r_text(r, m->reason, sizeof m->reason, &RULE_REASON);
}

static void dec_tick_begin(cs_reader *r, cs_tick_begin *t)
{
    uint8_t i;
    t->time_us = r_u64(r);
    t->wake_reason = r_u8(r);
    if (!r->err && (t->wake_reason & ~CS_WAKE_ALL) != 0u) {
        r_fail(r, R_WAKE_REASON);
        return;
    }
    t->sin_level = r_u8(r);
    if (!r->err && t->sin_level > 1u) {
        r_fail(r, R_SIN_LEVEL);
        return;
    }
    t->digital_in = r_u16(r);
    t->i2c_tx_queued = r_u16(r);

    t->n_servos = r_u8(r);
    if (r->err)
        return;
    if (t->n_servos > CS_SERVOS_MAX) {
        r_fail(r, R_N_SERVOS);
        return;
    }
    for (i = 0u; i < t->n_servos; i++)
        t->servo_pos[i] = r_i32(r);

    t->n_adc = r_u8(r);
    if (r->err)
        return;
    if (t->n_adc > CS_ADC_MAX) {
        r_fail(r, R_N_ADC);
        return;
    }
    for (i = 0u; i < t->n_adc; i++) {
        t->adc[i] = r_u16(r);
        if (!r->err && t->adc[i] > CS_ADC_COUNTS_MAX) {
            r_fail(r, R_ADC_VALUE);
            return;
        }
    }

    t->n_counters = r_u8(r);
    if (r->err)
        return;
    if (t->n_counters > CS_COUNTERS_MAX) {
        r_fail(r, R_N_COUNTERS);
        return;
    }
    for (i = 0u; i < t->n_counters; i++)
        t->counter[i] = r_i32(r);

    r_i2c_frames(r, &t->n_i2c, t->i2c);
}

static void dec_tick_end(cs_reader *r, cs_tick_end *t)
{
    uint8_t i;
    t->wake_time_us = r_u64(r);
    t->wake_events = r_u8(r);
    if (!r->err && (t->wake_events & ~(CS_WAKE_I2C | CS_WAKE_SIN_EDGE)) != 0u) {
        r_fail(r, R_WAKE_EVENTS);
        return;
    }
    t->sout_level = r_u8(r);
    if (!r->err && t->sout_level > 1u) {
        r_fail(r, R_SOUT_LEVEL);
        return;
    }
    t->i2c_address = r_u8(r);
    if (!r->err && t->i2c_address > 127u) {
        r_fail(r, R_OWN_ADDR);
        return;
    }
    t->n_servos = r_u8(r);
    if (r->err)
        return;
    if (t->n_servos > CS_SERVOS_MAX) {
        r_fail(r, R_N_SERVOS);
        return;
    }
    t->servo_enable = r_u8(r);
    if (!r->err && (t->servo_enable >> t->n_servos) != 0u) {
        r_fail(r, R_SERVO_ENABLE);
        return;
    }
    for (i = 0u; i < t->n_servos; i++)
        t->servo_setpoint[i] = r_i32(r);

    r_i2c_frames(r, &t->n_i2c, t->i2c);

    t->n_log = r_u8(r);
    if (r->err)
        return;
    if (t->n_log > CS_LOG_LINES_MAX) {
        r_fail(r, R_N_LOG);
        return;
    }
    for (i = 0u; i < t->n_log && !r->err; i++)
        r_text(r, t->log[i], sizeof t->log[i], &RULE_LOG_LINE);
}

int cs_decode(const uint8_t *body, size_t len, cs_msg *out, const char **reason)
{
    cs_reader r;
    if (!out || (!body && len != 0u)) {
        r.err = R_NULL_ARG;
    } else if (len < CS_TYPE_LEN) {
        r.err = R_NO_TYPE;
    } else if (len > CS_BODY_MAX) {
        r.err = R_BODY_TOO_LONG;
    } else {
        memset(out, 0, sizeof *out); /* unused entries read as zero */
        r.p = body;
        r.len = len;
        r.pos = 0u;
        r.err = 0;
        out->type = r_u16(&r);
        switch (out->type) {
        case CS_MSG_HELLO:
            dec_hello(&r, &out->u.hello);
            break;
        case CS_MSG_WELCOME:
            dec_welcome(&r, &out->u.welcome);
            break;
        case CS_MSG_REJECT:
            dec_reason(&r, &out->u.reject);
            break;
        case CS_MSG_TICK_BEGIN:
            dec_tick_begin(&r, &out->u.tick_begin);
            break;
        case CS_MSG_TICK_END:
            dec_tick_end(&r, &out->u.tick_end);
            break;
        case CS_MSG_SHUTDOWN:
            dec_reason(&r, &out->u.shutdown);
            break;
        default:
            r_fail(&r, R_UNKNOWN_TYPE);
            break;
        }
        if (!r.err && r.pos != r.len)
            r.err = R_TRAILING;
    }
    if (r.err) {
        if (reason)
            *reason = r.err;
        return CS_ERR;
    }
    return CS_OK;
}

const char *cs_msg_name(uint16_t type)
{
    switch (type) {
    case CS_MSG_HELLO:
        return "HELLO";
    case CS_MSG_WELCOME:
        return "WELCOME";
    case CS_MSG_REJECT:
        return "REJECT";
    case CS_MSG_TICK_BEGIN:
        return "TICK_BEGIN";
    case CS_MSG_TICK_END:
        return "TICK_END";
    case CS_MSG_SHUTDOWN:
        return "SHUTDOWN";
    default:
        return "unknown";
    }
}
