// status.c — the one printf-style formatter of error messages.
#include "core/status.h"

#include <stdarg.h>
#include <stdio.h>

glint_status status_fail(glint_error *err, glint_status status, const char *format, ...) {
    va_list ap;
    va_start(ap, format);
    vsnprintf(err->message, sizeof err->message, format, ap);
    va_end(ap);
    return status;
}
