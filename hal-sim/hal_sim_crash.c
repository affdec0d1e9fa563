/* hal-sim: a module's last words. At exit and on a crash the log lines queued
 * since the last wait are sent to the server (hs_send_last_words), so the line
 * logged just before the fault is in the module's log; a crash also prints a
 * backtrace to stderr, which the server sends to the module's .out file. */
#define _XOPEN_SOURCE 700 /* sigaltstack, SA_ONSTACK */

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#if defined(__GLIBC__)
#include <execinfo.h>
#endif

#include "hal_sim_link.h"

#define BACKTRACE_MAX 48

static const int crash_signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};

/* the crash handler runs on its own stack, so that a stack overflow can be reported */
static char alt_stack[64 * 1024];

static void put(const char *s)
{
    size_t n = strlen(s);
    while (n > 0) {
        ssize_t w = write(STDERR_FILENO, s, n);
        if (w <= 0)
            return;
        s += w;
        n -= (size_t)w;
    }
}

static const char *signal_name(int sig)
{
    switch (sig) {
    case SIGSEGV: return "SIGSEGV (segmentation fault)";
    case SIGBUS: return "SIGBUS (bus error)";
    case SIGFPE: return "SIGFPE (arithmetic exception)";
    case SIGILL: return "SIGILL (illegal instruction)";
    case SIGABRT: return "SIGABRT (abort)";
    default: return "a signal";
    }
}

static void on_crash(int sig)
{
    /* only async-signal-safe calls from here (backtrace's library was loaded
     * at installation) */
    hs_send_last_words();
#if defined(__GLIBC__)
    {
        void *frames[BACKTRACE_MAX];
        int n = backtrace(frames, BACKTRACE_MAX);
        put(CS_NOTICE_BACKTRACE);
        put(signal_name(sig));
        put(" (innermost first; for file:line run addr2line -f -C -e <program> <the +0x... offsets>):\n");
        backtrace_symbols_fd(frames, n, STDERR_FILENO);
    }
#else
    put("chainsim hal: ");
    put(signal_name(sig));
    put(" (no backtrace on this C library)\n");
#endif
    /* SA_RESETHAND restored the default action: die of the same signal, so
     * that the server reports it */
    raise(sig);
}

static void at_exit(void)
{
    hs_send_last_words();
}

void hs_install_crash_handlers(void)
{
    static int installed;
    struct sigaction sa;
    stack_t ss;
    size_t i;

    if (installed)
        return;
    installed = 1;
#if defined(__GLIBC__)
    {
        void *warm[1];
        (void)backtrace(warm, 1); /* loads libgcc now, not inside the handler */
    }
#endif
    memset(&ss, 0, sizeof ss);
    ss.ss_sp = alt_stack;
    ss.ss_size = sizeof alt_stack;
    (void)sigaltstack(&ss, NULL);

    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_crash;
    sa.sa_flags = SA_ONSTACK | SA_RESETHAND | SA_NODEFER;
    sigemptyset(&sa.sa_mask);
    for (i = 0; i < sizeof crash_signals / sizeof crash_signals[0]; i++)
        (void)sigaction(crash_signals[i], &sa, NULL);
    (void)atexit(at_exit);
}
