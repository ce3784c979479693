// file_read.c — a whole file into memory, refusing what is larger than a limit as soon as it is read.
#include "core/file_read.h"

#include <errno.h>
#include <stdlib.h>

char *file_read_stream(FILE *f, size_t initial, size_t max, size_t *len, int *errnum) {
    *errnum = 0;
    *len = 0;
    // Room for the NUL, and never more than one byte past the limit: enough to tell that it is too large.
    size_t cap = (initial < max ? initial : max) + 2, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - 1 - n, f);
        if (n > max) {
            *errnum = EFBIG;
            break;
        }
        if (n < cap - 1) { // a short read: the end of the file, or an error
            if (ferror(f)) *errnum = errno ? errno : EIO;
            break;
        }
        size_t bigger = cap - 1 > max / 2 ? max + 2 : cap * 2;
        char *grown = realloc(buf, bigger);
        if (!grown) break;
        buf = grown;
        cap = bigger;
    }
    if (!buf || (!*errnum && n == cap - 1)) *errnum = ENOMEM; // an allocation failed
    if (*errnum) {
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}
