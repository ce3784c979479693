// status.h — the vocabulary of every layer: what a call did (glint_status) and why it failed (glint_error),
// and the one helper that writes the message. The public header glint.h re-exports this file (installed as
// glint/status.h), so internal headers include it rather than glint.h and never depend on the API above them.
#ifndef GLINT_CORE_STATUS_H
#define GLINT_CORE_STATUS_H

/// What a call did. These are status values, not exit codes; the glint program exits with 0, 1 or 2 for
/// the first three, and with 128 + the signal's number (130 for SIGINT, 143 for SIGTERM) when a signal
/// stopped the render, after writing the partial image. 3 is never an exit code.
typedef enum glint_status {
    GLINT_OK = 0,
    GLINT_ERR_RENDER = 1,     ///< rendering, memory or I/O failure (the program exits 1)
    GLINT_ERR_INPUT = 2,      ///< bad usage, scene file, mesh or image file (the program exits 2)
    GLINT_ERR_INTERRUPTED = 3 ///< the render was stopped by its cancel token; the partial image is kept
} glint_status;

/// A value struct: a human-readable error, already formatted as "file:line:col: what is wrong, what was
/// expected". Every function that can fail fills it (when not NULL) whenever it returns a status other than
/// GLINT_OK.
typedef struct glint_error {
    char message[1024];
} glint_error;

#endif

// Internal alone (glint.h, which includes this file as glint/status.h, defines GLINT_PUBLIC_HEADER around it);
// guarded apart, so that it is declared even when glint.h came first.
#if !defined(GLINT_PUBLIC_HEADER) && !defined(GLINT_CORE_STATUS_FAIL)
#define GLINT_CORE_STATUS_FAIL
#include <stdarg.h>
#include <stddef.h>
/// The one formatter of messages: `prefix` (a reader's "file:line:col: ", "file:line: warning: ", or "") then the
/// printf-style message, into buf (size bytes, always terminated, cut when longer).
void status_vformat(char *buf, size_t size, const char *prefix, const char *format, va_list ap)
    __attribute__((format(printf, 4, 0)));
/// Formats the message into err (printf-style) and returns `status`: `return status_fail(err, GLINT_ERR_INPUT,
/// "%s: ...", path);`.
glint_status status_fail(glint_error *err, glint_status status, const char *format, ...)
    __attribute__((format(printf, 3, 4)));
#endif
