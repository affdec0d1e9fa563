/* hal-sim internal: the connection to the physics server and the state the
 * peripheral files share. Not part of the firmware-visible HAL.
 *
 * One module process = one blocking Unix-socket client. Outputs written by
 * the HAL calls are buffered in hs.out and sent as one TICK_END by
 * hs_exchange(), which then blocks for the next TICK_BEGIN and refreshes the
 * cached inputs. No allocation after hal_init(). */
#ifndef HAL_SIM_LINK_H
#define HAL_SIM_LINK_H

#include <stdint.h>

#include "chainsim_protocol.h"

#define HS_RX_RING 16u /* received I2C frames kept until hal_i2c_receive */

/* hal_wait_event_ms returned at once this many times in a row (a frame
 * waiting, unread): the module says so on stderr (CS_NOTICE_WAIT_SPINS),
 * where the server's hang report finds it */
#define HS_EARLY_RETURNS_NOTICE 1000000ul

/* process exit codes */
#define HS_EXIT_CONFIG 2   /* bad/missing environment, REJECT, hal_init not called */
#define HS_EXIT_PROTOCOL 3 /* server unreachable, EOF, undecodable or unexpected frame */

typedef struct {
    int fd;               /* -1 until hal_init() connected */
    uint16_t module_index;
    uint32_t tick_us;
    uint64_t seed;
    uint8_t n_params;
    cs_param params[CS_PARAMS_MAX];

    /* inputs, as of the latest TICK_BEGIN */
    uint64_t time_us;
    uint8_t sin_level;
    uint16_t digital_in;
    uint8_t n_servos;
    int32_t servo_pos[CS_SERVOS_MAX];
    uint8_t n_adc;
    uint16_t adc[CS_ADC_MAX];
    uint8_t n_counters;
    int32_t counter[CS_COUNTERS_MAX];
    uint16_t i2c_tx_queued; /* bytes of our frames still on the bus at the last TICK_BEGIN */

    /* persistent outputs (sent in every TICK_END) */
    uint8_t sout_level;
    uint8_t i2c_address;
    uint8_t servo_enable;
    int32_t servo_setpoint[CS_SERVOS_MAX]; /* millidegrees */

    /* per-wait outputs (cleared after each TICK_END) */
    uint8_t n_i2c_tx;
    cs_i2c_frame i2c_tx[CS_I2C_FRAMES_MAX];
    uint8_t n_log;
    char log[CS_LOG_LINES_MAX][CS_LOG_LINE_MAX];
    uint32_t log_dropped; /* lines dropped since the last TICK_END */

    /* received I2C frames, oldest first */
    cs_i2c_frame rx[HS_RX_RING];
    uint8_t rx_head;  /* index of the oldest frame */
    uint8_t rx_count;
    uint32_t rx_dropped; /* oldest frames overwritten since the last report */

    uint32_t early_returns; /* hal_wait_event_ms returns without a wait since the last one */
    uint8_t owes_tick_end;  /* a TICK_BEGIN was applied and no TICK_END sent since */
} hs_state;

extern hs_state hs;

/* print "chainsim hal: <msg>" to stderr and exit with code */
void hs_die(int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3), noreturn))
#endif
    ;

/* after WELCOME: a warning on stderr for each parameter the server sent
 * that hal_param_table does not declare (hal_param.c; it also makes every
 * program carry the --chainsim-params listing) */
void hs_params_check(void);

/* exit(2) with a message unless hal_init() has connected */
void hs_require_init(const char *caller);

/* connect to the Unix socket at path, retrying briefly while it does not exist
 * yet; exits(3) on failure */
void hs_connect(const char *path);

/* HELLO -> WELCOME (fills hs) -> first TICK_BEGIN; exits on REJECT/SHUTDOWN/error */
void hs_handshake(uint16_t module_index, const char *type_name);

/* send one TICK_END (buffered outputs, wake_time_us, wake_events), clear the
 * per-wait outputs, block for the next TICK_BEGIN and apply it. Returns its
 * wake_reason. Exits the process on SHUTDOWN (0), EOF or protocol error (3). */
uint8_t hs_exchange(uint64_t wake_time_us, uint8_t wake_events);

/* queue a log line (truncated); counts a drop when the queue is full */
void hs_log_line(const char *line);

/* A process about to die keeps its last words: the log lines queued since the
 * last wait go out in one last TICK_END (no I2C frames), without waiting for
 * an answer. Plain send(), failures ignored: safe in a signal handler and at
 * exit. Does nothing when no TICK_END is owed or nothing is queued. */
void hs_send_last_words(void);

/* after the handshake: at exit and on a crash (SIGSEGV, SIGBUS, SIGFPE,
 * SIGILL, SIGABRT) send the last words; on a crash also print a backtrace to
 * stderr (the module's .out file), then die of the same signal */
void hs_install_crash_handlers(void);

#endif /* HAL_SIM_LINK_H */
