/* hal-sim: the socket link to the physics server (see hal_sim_link.h). */
#define _POSIX_C_SOURCE 200809L

#include "hal_sim_link.h"

#include <errno.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#ifndef SOCK_CLOEXEC
#include <fcntl.h>
#endif
#ifndef MSG_NOSIGNAL
#define MSG_NOSIGNAL 0
#endif

#define CONNECT_RETRY_MS 10
#define CONNECT_TIMEOUT_MS 3000

hs_state hs = {.fd = -1};

/* frame buffers and the message structs: static, reused every tick */
static uint8_t tx_buf[4u + CS_BODY_MAX];
static uint8_t rx_buf[2u * (4u + CS_BODY_MAX)];
static size_t rx_pos; /* first unconsumed byte */
static size_t rx_len; /* bytes held */
static cs_msg tx_msg;
static cs_msg rx_msg;

void hs_die(int code, const char *fmt, ...)
{
    va_list ap;
    fputs("chainsim hal: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(code);
}

void hs_require_init(const char *caller)
{
    if (hs.fd < 0)
        hs_die(HS_EXIT_CONFIG, "%s() called before hal_init()", caller);
}

static void sleep_ms(long ms)
{
    struct timespec ts;
    ts.tv_sec = ms / 1000;
    ts.tv_nsec = (ms % 1000) * 1000000L;
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

void hs_connect(const char *path)
{
    struct sockaddr_un sa;
    long waited = 0;
    size_t n = strlen(path);

    if (n == 0 || n >= sizeof sa.sun_path)
        hs_die(HS_EXIT_CONFIG, "CHAINSIM_SOCKET: path length %zu not in 1..%zu", n,
               sizeof sa.sun_path - 1);
    memset(&sa, 0, sizeof sa);
    sa.sun_family = AF_UNIX;
    memcpy(sa.sun_path, path, n + 1);

    for (;;) {
        int fd;
#ifdef SOCK_CLOEXEC
        fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
#else
        fd = socket(AF_UNIX, SOCK_STREAM, 0);
        if (fd >= 0)
            fcntl(fd, F_SETFD, FD_CLOEXEC);
#endif
        if (fd < 0)
            hs_die(HS_EXIT_PROTOCOL, "socket(): %s", strerror(errno));
        if (connect(fd, (const struct sockaddr *)&sa, sizeof sa) == 0) {
            hs.fd = fd;
            return;
        }
        {
            int e = errno;
            close(fd);
            if ((e == ENOENT || e == ECONNREFUSED || e == EINTR || e == EAGAIN) &&
                waited < CONNECT_TIMEOUT_MS) {
                sleep_ms(CONNECT_RETRY_MS);
                waited += CONNECT_RETRY_MS;
                continue;
            }
            hs_die(HS_EXIT_PROTOCOL, "cannot connect to %s (CHAINSIM_SOCKET): %s", path,
                   strerror(e));
        }
    }
}

/* ---- framing ------------------------------------------------------------ */

/* send the first n bytes of tx_buf; 0, or the errno of the failure. Plain
 * send() only: also used from a signal handler (hs_send_last_words) */
static int send_tx(size_t n)
{
    size_t off = 0;
    while (off < n) { /* normally a single send() */
        ssize_t w = send(hs.fd, tx_buf + off, n - off, MSG_NOSIGNAL);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return w < 0 ? errno : EPIPE;
        off += (size_t)w;
    }
    return 0;
}

static void send_msg(const cs_msg *m)
{
    const char *reason = "?";
    size_t n = cs_encode(m, tx_buf, sizeof tx_buf, &reason);
    int err;

    if (n == 0)
        hs_die(HS_EXIT_PROTOCOL, "cannot encode %s: %s", cs_msg_name(m->type), reason);
    err = send_tx(n);
    if (err == EPIPE || err == ECONNRESET)
        hs_die(HS_EXIT_PROTOCOL, "server closed the connection");
    if (err != 0)
        hs_die(HS_EXIT_PROTOCOL, "send(): %s", strerror(err));
}

/* make at least need bytes available at rx_buf + rx_pos */
static void rx_fill(size_t need)
{
    if (rx_len - rx_pos >= need)
        return;
    if (rx_pos > 0) {
        memmove(rx_buf, rx_buf + rx_pos, rx_len - rx_pos);
        rx_len -= rx_pos;
        rx_pos = 0;
    }
    while (rx_len < need) {
        ssize_t r;
        /* Wait in poll() for input only, not in read(): a task blocked in
         * read() on a Unix stream socket is woken on every wake-up of the
         * socket, including "send space freed" when the server reads this
         * module's last TickEnd, which comes while the module waits for its
         * next TickBegin. poll() for POLLIN is not woken by those, which
         * saves one context switch and one cross-CPU wake-up per exchange. */
        struct pollfd p;
        p.fd = hs.fd;
        p.events = POLLIN;
        p.revents = 0;
        if (poll(&p, 1, -1) < 0) {
            if (errno == EINTR)
                continue;
            hs_die(HS_EXIT_PROTOCOL, "poll(): %s", strerror(errno));
        }
        r = read(hs.fd, rx_buf + rx_len, sizeof rx_buf - rx_len);
        if (r > 0) {
            rx_len += (size_t)r;
        } else if (r == 0) {
            if (rx_len == 0)
                hs_die(HS_EXIT_PROTOCOL, "server closed the connection");
            hs_die(HS_EXIT_PROTOCOL, "server closed the connection inside a frame");
        } else if (errno != EINTR) {
            hs_die(HS_EXIT_PROTOCOL, "read(): %s", strerror(errno));
        }
    }
}

/* read and decode the next frame into rx_msg */
static const cs_msg *recv_msg(void)
{
    uint32_t body_len = 0;
    const char *reason = "?";

    rx_fill(4);
    if (cs_body_length(rx_buf + rx_pos, &body_len, &reason) != CS_OK)
        hs_die(HS_EXIT_PROTOCOL, "bad frame length from server: %s", reason);
    rx_fill(4u + body_len);
    if (cs_decode(rx_buf + rx_pos + 4, body_len, &rx_msg, &reason) != CS_OK)
        hs_die(HS_EXIT_PROTOCOL, "undecodable frame from server: %s", reason);
    rx_pos += 4u + body_len;
    return &rx_msg;
}

/* ---- inputs -------------------------------------------------------------- */

static void rx_push(const cs_i2c_frame *f)
{
    uint8_t slot;
    if (hs.rx_count == HS_RX_RING) { /* drop the oldest */
        hs.rx_head = (uint8_t)((hs.rx_head + 1u) % HS_RX_RING);
        hs.rx_count--;
        hs.rx_dropped++;
    }
    slot = (uint8_t)((hs.rx_head + hs.rx_count) % HS_RX_RING);
    hs.rx[slot] = *f;
    hs.rx_count++;
}

static void apply_tick_begin(const cs_tick_begin *tb)
{
    uint8_t i;
    hs.time_us = tb->time_us;
    hs.sin_level = tb->sin_level;
    hs.digital_in = tb->digital_in;
    hs.i2c_tx_queued = tb->i2c_tx_queued;
    hs.n_servos = tb->n_servos;
    for (i = 0; i < tb->n_servos && i < CS_SERVOS_MAX; i++)
        hs.servo_pos[i] = tb->servo_pos[i];
    hs.n_adc = tb->n_adc;
    for (i = 0; i < tb->n_adc && i < CS_ADC_MAX; i++)
        hs.adc[i] = tb->adc[i];
    hs.n_counters = tb->n_counters;
    for (i = 0; i < tb->n_counters && i < CS_COUNTERS_MAX; i++)
        hs.counter[i] = tb->counter[i];
    for (i = 0; i < tb->n_i2c && i < CS_I2C_FRAMES_MAX; i++)
        rx_push(&tb->i2c[i]);
}

/* block for the next TICK_BEGIN; SHUTDOWN exits 0, anything else exits 3 */
static uint8_t await_tick_begin(const char *after)
{
    const cs_msg *m = recv_msg();
    if (m->type == CS_MSG_TICK_BEGIN) {
        apply_tick_begin(&m->u.tick_begin);
        hs.owes_tick_end = 1;
        return m->u.tick_begin.wake_reason;
    }
    if (m->type == CS_MSG_SHUTDOWN)
        exit(0);
    hs_die(HS_EXIT_PROTOCOL, "expected TICK_BEGIN after %s, got %s", after,
           cs_msg_name(m->type));
}

/* ---- handshake ----------------------------------------------------------- */

void hs_handshake(uint16_t module_index, const char *type_name)
{
    const cs_msg *m;
    memset(&tx_msg, 0, sizeof tx_msg);
    tx_msg.type = CS_MSG_HELLO;
    tx_msg.u.hello.magic = (uint32_t)CS_MAGIC;
    tx_msg.u.hello.version = CS_VERSION;
    tx_msg.u.hello.module_index = module_index;
    tx_msg.u.hello.pid = (uint32_t)getpid();
    strncpy(tx_msg.u.hello.type, type_name, CS_TYPE_NAME_MAX - 1);
    send_msg(&tx_msg);

    m = recv_msg();
    switch (m->type) {
    case CS_MSG_WELCOME:
        break;
    case CS_MSG_REJECT:
        fprintf(stderr, "chainsim hal: server rejected module %u (%s): %s\n",
                (unsigned)module_index, type_name, m->u.reject.reason);
        exit(HS_EXIT_CONFIG);
    case CS_MSG_SHUTDOWN:
        exit(0);
    default:
        hs_die(HS_EXIT_PROTOCOL, "expected WELCOME after HELLO, got %s", cs_msg_name(m->type));
    }
    if (m->u.welcome.module_index != module_index)
        hs_die(HS_EXIT_PROTOCOL, "WELCOME for module %u, I am module %u",
               (unsigned)m->u.welcome.module_index, (unsigned)module_index);
    if (m->u.welcome.tick_us == 0)
        hs_die(HS_EXIT_PROTOCOL, "WELCOME with tick_us 0");
    hs.module_index = module_index;
    hs.tick_us = m->u.welcome.tick_us;
    hs.seed = m->u.welcome.seed;
    hs.n_params = m->u.welcome.n_params;
    memcpy(hs.params, m->u.welcome.params, sizeof hs.params);

    (void)await_tick_begin("WELCOME");
    hs_install_crash_handlers();
}

/* ---- the lockstep exchange ----------------------------------------------- */

void hs_log_line(const char *line)
{
    if (hs.n_log >= CS_LOG_LINES_MAX) {
        hs.log_dropped++;
        return;
    }
    strncpy(hs.log[hs.n_log], line, CS_LOG_LINE_MAX - 1);
    hs.log[hs.n_log][CS_LOG_LINE_MAX - 1] = '\0';
    hs.n_log++;
}

/* small decimal formatter (no snprintf in the per-tick path) */
static char *put_u32(char *p, uint32_t v)
{
    char tmp[10];
    int n = 0;
    do {
        tmp[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0);
    while (n > 0)
        *p++ = tmp[--n];
    return p;
}

static void build_line(char *dst, const char *a, uint32_t n, const char *b)
{
    size_t la = strlen(a);
    memcpy(dst, a, la);
    dst = put_u32(dst + la, n);
    strcpy(dst, b);
}

/* the TICK_END of this wait into tx_msg: the persistent outputs, the queued
 * log lines and, with_i2c, the queued I2C frames */
static void fill_tick_end(uint64_t wake_time_us, uint8_t wake_events, int with_i2c)
{
    cs_tick_end *te = &tx_msg.u.tick_end;
    uint8_t i;

    tx_msg.type = CS_MSG_TICK_END;
    te->wake_time_us = wake_time_us;
    te->wake_events = (uint8_t)(wake_events & (CS_WAKE_I2C | CS_WAKE_SIN_EDGE));
    te->sout_level = hs.sout_level;
    te->i2c_address = hs.i2c_address;
    te->n_servos = hs.n_servos;
    te->servo_enable = (uint8_t)(hs.servo_enable & ((1u << hs.n_servos) - 1u));
    for (i = 0; i < CS_SERVOS_MAX; i++)
        te->servo_setpoint[i] = i < hs.n_servos ? hs.servo_setpoint[i] : 0;
    te->n_i2c = with_i2c ? hs.n_i2c_tx : 0;
    for (i = 0; i < te->n_i2c; i++)
        te->i2c[i] = hs.i2c_tx[i];
    te->n_log = hs.n_log;
    for (i = 0; i < hs.n_log; i++)
        memcpy(te->log[i], hs.log[i], CS_LOG_LINE_MAX);
}

uint8_t hs_exchange(uint64_t wake_time_us, uint8_t wake_events)
{
    hs.owes_tick_end = 0; /* from here on last words would interleave with this frame */
    hs.early_returns = 0;
    if (hs.rx_dropped != 0) {
        char line[64];
        build_line(line, "i2c: ", hs.rx_dropped, " received frames dropped (ring full)");
        hs.rx_dropped = 0;
        hs_log_line(line);
    }
    if (hs.log_dropped != 0) {
        /* the last slot carries the notice instead of a line */
        uint32_t dropped = hs.log_dropped;
        if (hs.n_log == CS_LOG_LINES_MAX) {
            hs.n_log--;
            dropped++;
        }
        build_line(hs.log[hs.n_log], "log: ", dropped, " lines dropped");
        hs.n_log++;
        hs.log_dropped = 0;
    }

    fill_tick_end(wake_time_us, wake_events, 1);
    send_msg(&tx_msg);
    hs.n_i2c_tx = 0;
    hs.n_log = 0;

    return await_tick_begin("TICK_END");
}

void hs_send_last_words(void)
{
    const char *reason = "?";
    size_t n;

    if (hs.fd < 0 || !hs.owes_tick_end || hs.n_log == 0)
        return;
    hs.owes_tick_end = 0;
    fill_tick_end(hs.time_us + hs.tick_us, 0, 0);
    n = cs_encode(&tx_msg, tx_buf, sizeof tx_buf, &reason);
    if (n != 0 && send_tx(n) == 0)
        hs.n_log = 0;
}
