// signals.h — the stop signals of glint and glint-mpi (SIGINT, SIGTERM, SIGHUP), handled once for both: while
// the scene is read a signal ends the program at once (nothing exists yet to write, and the read may be blocked
// on a FIFO); during the render the first one asks it to stop, and the program then writes what it has; a second
// one ends it by the signal's default action, so that the shell sees the usual status.
#ifndef GLINT_CLI_SIGNALS_H
#define GLINT_CLI_SIGNALS_H

#include "glint.h"

#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>

/// Installs the handlers (even for a signal inherited as ignored, so that a harness can always interrupt a
/// render). `program` prefixes the loading message, printed unless `quiet`. The first signal during the render
/// requests `cancel` (glint's render token) and sets `flag` (glint-mpi's stop flag); either may be NULL.
/// The program starts in the loading state.
void cli_signals_install(const char *program, bool quiet, glint_cancel *cancel, atomic_int *flag);
/// Leaves the loading state: from now on a signal stops the render instead of ending the program.
void cli_signals_loaded(void);
/// The signal that asked the render to stop, 0 while none has (set from the handler).
atomic_int *cli_signals_first(void);
/// The conventional status of a program stopped by a signal: 128 + its number (130 for SIGINT when none came).
int cli_signals_status(void);
/// Fills *set with the stop signals.
void cli_stop_signals(sigset_t *set);
/// Holds the stop signals back (this thread and the threads it starts), so that a rename never races an abort.
void cli_signals_block(void);
/// Lets them in again.
void cli_signals_unblock(void);

#endif
