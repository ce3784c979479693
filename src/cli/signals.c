// signals.c — one handler for the stop signals of both programs; its state is four atomics and flags set before
// the handler is installed, which is all a handler may touch.
#include "signals.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler needs a lock-free atomic int");

static const int STOP_SIGNALS[] = {SIGINT, SIGTERM, SIGHUP};
enum { STOP_SIGNAL_COUNT = sizeof STOP_SIGNALS / sizeof STOP_SIGNALS[0], MESSAGE_BYTES = 96 };

static atomic_int first_signal; // the signal that asked the render to stop, 0 while none has
static atomic_int loading;      // 1 while the scene is read: a signal then ends the program at once
static glint_cancel *render_token;
static atomic_int *stop_flag;
static char loading_message[MESSAGE_BYTES]; // "PROGRAM: interrupted while loading the scene\n", or empty (quiet)
static size_t loading_length;
static char again_message[MESSAGE_BYTES]; // "\nPROGRAM: interrupted again, aborting\n"
static size_t again_length;

static void on_signal(int sig) {
    if (atomic_load(&loading)) {
        if (loading_length) {
            ssize_t ignored = write(STDERR_FILENO, loading_message, loading_length);
            (void)ignored;
        }
        _exit(128 + sig);
    }
    int expected = 0;
    if (atomic_compare_exchange_strong(&first_signal, &expected, sig)) {
        if (render_token) glint_cancel_request(render_token);
        if (stop_flag) atomic_store(stop_flag, 1);
        return;
    }
    ssize_t ignored = write(STDERR_FILENO, again_message, again_length);
    (void)ignored;
    struct sigaction dfl;
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    sigaction(sig, &dfl, NULL);
    raise(sig); // delivered as soon as this handler returns
}

void cli_signals_install(const char *program, bool quiet, glint_cancel *cancel, atomic_int *flag) {
    render_token = cancel;
    stop_flag = flag;
    loading_length = 0;
    if (!quiet) {
        int m = snprintf(loading_message, sizeof loading_message, "%s: interrupted while loading the scene\n", program);
        loading_length = m > 0 && (size_t)m < sizeof loading_message ? (size_t)m : 0;
    }
    int n = quiet ? 0 : snprintf(again_message, sizeof again_message, "\n%s: interrupted again, aborting\n", program);
    again_length = n > 0 && (size_t)n < sizeof again_message ? (size_t)n : 0;
    atomic_store(&loading, 1);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    for (int i = 0; i < STOP_SIGNAL_COUNT; i++) sigaction(STOP_SIGNALS[i], &sa, NULL);
}

void cli_signals_loaded(void) { atomic_store(&loading, 0); }

atomic_int *cli_signals_first(void) { return &first_signal; }

int cli_signals_status(void) {
    int sig = atomic_load(&first_signal);
    return 128 + (sig ? sig : SIGINT);
}

void cli_stop_signals(sigset_t *set) {
    sigemptyset(set);
    for (int i = 0; i < STOP_SIGNAL_COUNT; i++) sigaddset(set, STOP_SIGNALS[i]);
}

void cli_signals_block(void) {
    sigset_t set;
    cli_stop_signals(&set);
    pthread_sigmask(SIG_BLOCK, &set, NULL);
}

void cli_signals_unblock(void) {
    sigset_t set;
    cli_stop_signals(&set);
    pthread_sigmask(SIG_UNBLOCK, &set, NULL);
}
