/* chainsim wire protocol between the physics server and module processes.
 *
 * C99, no allocation. Every frame on the Unix stream socket is
 *
 *     u32 body_length (little-endian) | body
 *     body = u16 message type | payload
 *
 * All integers are little-endian and fixed width; every count is bounded by
 * the CS_*_MAX limits below and the decoder rejects anything larger, shorter,
 * longer or otherwise malformed with a reason, never reading out of bounds.
 * See docs/protocol.md for the sequence of messages.
 */
#ifndef CHAINSIM_PROTOCOL_H
#define CHAINSIM_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define CS_MAGIC 0x4D534843UL /* "CHSM" as little-endian bytes */
#define CS_VERSION 2u /* 2: TICK_BEGIN says how much of the module's I2C output is still on the bus */

/* Lines the simulated HAL prints on a module's stderr (its .out file) that
 * the server looks for when it reports a fault: a wait that spins without
 * sleeping, and a crash's backtrace. */
#define CS_NOTICE_WAIT_SPINS "hal_wait_event_ms(HAL_EV_I2C) returned at once with an I2C frame waiting,"
#define CS_NOTICE_BACKTRACE "chainsim hal: backtrace of "

/* A program started with the argument CS_PARAMS_ARG prints its parameter
 * declarations (hal_param.h) on stdout and exits 0, before main: the line
 * CS_PARAMS_HEADER, then one line per parameter,
 *     name TAB type TAB min TAB max TAB default TAB meaning
 * (type: uint8, int16, uint16, int32, uint32). The server reads it before a
 * run to check the scene's parameters; `chainsim params` shows it. */
#define CS_PARAMS_ARG "--chainsim-params"
#define CS_PARAMS_HEADER "chainsim-params 1"

/* hard limits: the decoder rejects frames that exceed any of them */
#define CS_BODY_MAX 2048u       /* bytes of body after the length prefix */
#define CS_TYPE_NAME_MAX 16u    /* module type name buffer, NUL included */
#define CS_SERVOS_MAX 4u        /* servos per module */
#define CS_ADC_MAX 8u           /* ADC channels per module */
#define CS_ADC_COUNTS_MAX 1023u /* 10-bit converter */
#define CS_COUNTERS_MAX 4u      /* encoder counters per module */
#define CS_I2C_FRAMES_MAX 8u    /* I2C frames per tick, each direction */
#define CS_I2C_DATA_MAX 32u     /* payload bytes of one I2C frame */
/* bytes (address + data) of a module's own frames that may wait on the bus,
 * as a board's send queue: a send past it is HAL_ERR_FULL, and the server
 * drops a frame a module sends past it (its events.jsonl names the module) */
#define CS_I2C_TX_QUEUE_MAX 512u
#define CS_LOG_LINES_MAX 4u     /* log lines per tick */
#define CS_LOG_LINE_MAX 96u     /* log line buffer, NUL included */
#define CS_PARAMS_MAX 16u       /* named integer parameters in WELCOME */
#define CS_PARAM_NAME_MAX 16u   /* parameter name buffer, NUL included */
#define CS_REASON_MAX 96u       /* REJECT / SHUTDOWN reason, NUL included */

/* message types */
enum cs_msg_type {
    CS_MSG_HELLO = 1,      /* module -> server: who I am */
    CS_MSG_WELCOME = 2,    /* server -> module: accepted, with configuration */
    CS_MSG_REJECT = 3,     /* server -> module: handshake refused, with reason */
    CS_MSG_TICK_BEGIN = 4, /* server -> module: time, inputs, received frames */
    CS_MSG_TICK_END = 5,   /* module -> server: outputs and next wake-up */
    CS_MSG_SHUTDOWN = 6    /* server -> module: run is over, exit now */
};

/* wake events a sleeping module asks for (cs_tick_end.wake_events) and the
 * reasons it was woken (cs_tick_begin.wake_reason) */
#define CS_WAKE_TIMER 0x01u    /* wake_time_us reached */
#define CS_WAKE_I2C 0x02u      /* an I2C frame for this module arrived */
#define CS_WAKE_SIN_EDGE 0x04u /* the Sin line changed level */
#define CS_WAKE_ALL 0x07u

/* return codes of cs_decode / cs_encode / cs_body_length */
#define CS_OK 0
#define CS_ERR -1

typedef struct {
    uint32_t magic;                /* CS_MAGIC */
    uint16_t version;              /* CS_VERSION */
    uint16_t module_index;         /* position in the chain; central = module count */
    uint32_t pid;                  /* the module process id */
    char type[CS_TYPE_NAME_MAX];   /* module type name, NUL-terminated */
} cs_hello;

typedef struct {
    char name[CS_PARAM_NAME_MAX];  /* NUL-terminated, non-empty */
    int32_t value;
} cs_param;

typedef struct {
    uint16_t version;      /* CS_VERSION */
    uint16_t module_index; /* echoed */
    uint32_t tick_us;      /* HAL timer tick */
    uint64_t seed;         /* scene seed, for firmware that wants randomness */
    uint8_t n_params;
    cs_param params[CS_PARAMS_MAX];
} cs_welcome;

typedef struct {
    char reason[CS_REASON_MAX]; /* NUL-terminated */
} cs_reason;

typedef struct {
    uint8_t addr;                  /* 7-bit destination address, 0 = general call */
    uint8_t len;                   /* 1..CS_I2C_DATA_MAX */
    uint8_t data[CS_I2C_DATA_MAX];
} cs_i2c_frame;

typedef struct {
    uint64_t time_us;     /* simulated time of this tick */
    uint8_t wake_reason;  /* CS_WAKE_* bits that woke the module */
    uint8_t sin_level;    /* 0 or 1 */
    uint16_t digital_in;  /* digital input pins, bit n = pin n (touch sensors) */
    uint16_t i2c_tx_queued; /* bytes of this module's frames still waiting on or crossing the bus */
    uint8_t n_servos;
    int32_t servo_pos[CS_SERVOS_MAX]; /* measured: millidegrees (rotary), micrometres (linear),
                                         the echoed command (screw drive, DC motor) */
    uint8_t n_adc;
    uint16_t adc[CS_ADC_MAX];         /* counts, 0..CS_ADC_COUNTS_MAX */
    uint8_t n_counters;
    int32_t counter[CS_COUNTERS_MAX]; /* encoder counts */
    uint8_t n_i2c;
    cs_i2c_frame i2c[CS_I2C_FRAMES_MAX]; /* frames delivered to this module */
} cs_tick_begin;

typedef struct {
    uint64_t wake_time_us; /* next time the module wants to run (> time of the tick) */
    uint8_t wake_events;   /* CS_WAKE_I2C / CS_WAKE_SIN_EDGE that may wake it earlier */
    uint8_t sout_level;    /* 0 or 1 */
    uint8_t i2c_address;   /* own 7-bit slave address, 0 = none yet */
    uint8_t n_servos;
    uint8_t servo_enable;  /* bit n: servo n is driven (0 = set-point ignored) */
    int32_t servo_setpoint[CS_SERVOS_MAX]; /* millidegrees (rotary), micrometres (linear),
                                              a screw drive's or DC motor's command as a
                                              servo pulse: +-90000 = full reverse/forward */
    uint8_t n_i2c;
    cs_i2c_frame i2c[CS_I2C_FRAMES_MAX];   /* frames to put on the bus */
    uint8_t n_log;
    char log[CS_LOG_LINES_MAX][CS_LOG_LINE_MAX]; /* NUL-terminated lines */
} cs_tick_end;

typedef struct {
    uint16_t type; /* enum cs_msg_type */
    union {
        cs_hello hello;
        cs_welcome welcome;
        cs_reason reject;
        cs_tick_begin tick_begin;
        cs_tick_end tick_end;
        cs_reason shutdown;
    } u;
} cs_msg;

/* encode m as a complete frame (length prefix included) into buf; returns the
 * number of bytes written, or 0 if m breaks a limit or cap is too small
 * (then *reason, if given, says why) */
size_t cs_encode(const cs_msg *m, uint8_t *buf, size_t cap, const char **reason);

/* read the 4-byte length prefix; CS_ERR (with *reason) if the body length is
 * 0, shorter than a type field or over CS_BODY_MAX */
int cs_body_length(const uint8_t prefix[4], uint32_t *body_len, const char **reason);

/* decode one body (without its length prefix) into *out; CS_ERR with *reason
 * for an unknown type, a truncated or overlong body, a count over its limit,
 * an unterminated or empty name, a level not 0/1, a bad magic or version */
int cs_decode(const uint8_t *body, size_t len, cs_msg *out, const char **reason);
/* Notes (both directions): *out is zeroed before decoding, so array entries
 * beyond their count read as 0; after CS_ERR its contents are unspecified.
 * *reason is only written on failure and is a static string naming the field.
 * Strings travel as u8 length + bytes (no NUL); names (type, param) must be
 * non-empty without control characters, texts (log lines, reasons) may be
 * empty but must not contain NUL. An accepted body re-encodes to the same
 * bytes. Largest frames (prefix included): HELLO 34, WELCOME 343, REJECT and
 * SHUTDOWN 102, TICK_BEGIN 342, TICK_END 693. */

/* name of a message type, "unknown" if none */
const char *cs_msg_name(uint16_t type);

#ifdef __cplusplus
}
#endif

#endif /* CHAINSIM_PROTOCOL_H */
