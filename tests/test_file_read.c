// test_file_read.c — reading a stream whole: the bytes and a terminating NUL, empty streams, the size limit
// checked while reading (exactly max bytes pass, max + 1 are refused), whatever the first guess of the size.
#include "check.h"
#include "core/file_read.h"

#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

// A temporary stream holding n bytes of a repeating pattern, rewound.
static FILE *stream_of(size_t n) {
    FILE *f = tmpfile();
    for (size_t i = 0; f && i < n; i++) fputc('a' + (int)(i % 26), f);
    if (f) rewind(f);
    return f;
}

static void check_read(size_t n, size_t initial, size_t max) {
    FILE *f = stream_of(n);
    CHECK(f != NULL);
    if (!f) return;
    size_t len = 99;
    int e = -1;
    char *buf = file_read_stream(f, initial, max, &len, &e);
    fclose(f);
    if (n > max) {
        CHECK(buf == NULL && e == EFBIG);
        return;
    }
    CHECK(buf != NULL && e == 0 && len == n);
    bool same = buf != NULL && buf[n] == '\0';
    for (size_t i = 0; same && i < n; i++) same = buf[i] == 'a' + (int)(i % 26);
    CHECK(same);
    free(buf);
}

int main(void) {
    const size_t sizes[] = {0, 1, 2, 15, 16, 17, 1000, 70000};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        size_t n = sizes[i];
        check_read(n, 0, 100000);      // no idea of the size: the buffer grows
        check_read(n, n, 100000);      // the size known
        check_read(n, 5, n);           // exactly at the limit
        if (n > 0) check_read(n, 0, n - 1); // one byte past it: refused
    }
    return check_summary();
}
