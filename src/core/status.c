// status.c — the one printf-style formatter of messages, errors and warnings alike.
#include "core/status.h"

#include <stdarg.h>
#include <stdio.h>

void status_vformat(char *buf, size_t size, const char *prefix, const char *format, va_list ap) {
    if (size == 0) return;
    int k = snprintf(buf, size, "%s", prefix);
    if (k >= 0 && (size_t)k < size) vsnprintf(buf + k, size - (size_t)k, format, ap);
}

glint_status status_fail(glint_error *err, glint_status status, const char *format, ...) {
    va_list ap;
    va_start(ap, format);
    status_vformat(err->message, sizeof err->message, "", format, ap);
    va_end(ap);
    return status;
}
