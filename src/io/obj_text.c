// obj_text.c — the text of OBJ and MTL files: tokens, numbers and indices, "file:line: ..." messages and warnings,
// names resolved against a file's directory, whole files read under a size limit.
#include "io/obj_text.h"
#include "core/file_read.h"
#include "core/filepath.h"
#include "io/decimal.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

// ---------------------------------------------------------------------------------------------------------
// Messages

// At most OBJ_QUOTE_MAX characters, and "..." after them; anything unprintable shown as '?'.
obj_quoted obj_quote(const char *s, size_t n) {
    obj_quoted q;
    size_t k = 0;
    for (size_t i = 0; i < n && k < OBJ_QUOTE_MAX; i++) {
        unsigned char c = (unsigned char)s[i];
        q.s[k++] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    if (n > OBJ_QUOTE_MAX) {
        memcpy(q.s + k, "...", 3);
        k += 3;
    }
    q.s[k] = '\0';
    return q;
}

// A file name fit for a message: as obj_quote(), but a long one keeps its end (the file name), not its start.
obj_quoted obj_quote_path(const char *s, size_t n) {
    if (n <= OBJ_QUOTE_MAX) return obj_quote(s, n);
    obj_quoted tail = obj_quote(s + n - OBJ_QUOTE_MAX, OBJ_QUOTE_MAX), q;
    memcpy(q.s, "...", 3);
    memcpy(q.s + 3, tail.s, OBJ_QUOTE_MAX + 1);
    return q;
}

// "file:line: " and the message.
bool obj_fail(obj_reporter *r, const char *fmt, ...) {
    if (!r->err) return false;
    char prefix[400];
    snprintf(prefix, sizeof prefix, "%s:%ld: ", r->name, r->line);
    va_list ap;
    va_start(ap, fmt);
    status_vformat(r->err->message, sizeof r->err->message, prefix, fmt, ap);
    va_end(ap);
    return false;
}

// "file:line: out of memory"; the load then fails with GLINT_ERR_RENDER.
bool obj_out_of_memory(obj_reporter *r) {
    r->nomem = true;
    return obj_fail(r, "out of memory");
}

// The warning, counted, and passed to the callback when there is one.
void obj_warn_at(obj_reporter *r, long line, const char *fmt, ...) {
    (*r->warnings)++;
    if (!r->warn) return;
    char buf[1200], prefix[400];
    if (line > 0) snprintf(prefix, sizeof prefix, "%s:%ld: warning: ", r->name, line);
    else snprintf(prefix, sizeof prefix, "%s: warning: ", r->name);
    va_list ap;
    va_start(ap, fmt);
    status_vformat(buf, sizeof buf, prefix, fmt, ap);
    va_end(ap);
    r->warn(buf, r->user);
}

// Unsupported statements are reported once per keyword and file, so a file full of `l` lines warns once.
void obj_warn_unsupported(obj_reporter *r, const char *kw, size_t n) {
    obj_quoted q = obj_quote(kw, n);
    for (int i = 0; i < r->ignored_count; i++)
        if (strcmp(r->ignored[i], q.s) == 0) return;
    if (r->ignored_count == OBJ_MAX_IGNORED_KEYWORDS) return;
    memcpy(r->ignored[r->ignored_count++], q.s, sizeof q.s);
    obj_warn_at(r, r->line, "'%s' statements are not supported; ignored (reported once)", q.s);
}

// ---------------------------------------------------------------------------------------------------------
// Tokens and numbers

// The rest of the line without surrounding blanks and without a comment that starts after a blank.
void obj_rest_of_line(obj_cursor *c, const char **s, size_t *n) {
    const char *p = c->p;
    while (p < c->end && obj_is_space(*p)) p++;
    const char *start = p, *stop = c->end;
    if (p < c->end && *p == '#') stop = p;
    for (const char *q = p + 1; q < c->end && stop == c->end; q++)
        if (*q == '#' && obj_is_space(q[-1])) stop = q;
    while (stop > start && obj_is_space(stop[-1])) stop--;
    *s = start;
    *n = (size_t)(stop - start);
    c->p = c->end;
}

bool obj_token_is(const char *tok, size_t n, const char *word) {
    size_t k = strlen(word);
    return n == k && memcmp(tok, word, k) == 0;
}

static bool number_error(obj_reporter *r, decimal_status st, const char *tok, size_t n) {
    if (st == DECIMAL_NOMEM) return obj_out_of_memory(r);
    obj_quoted q = obj_quote(tok, n);
    if (st == DECIMAL_NOT_FINITE) return obj_fail(r, "'%s' is not a finite number, expected a decimal number", q.s);
    if (st == DECIMAL_RANGE) return obj_fail(r, "number '%s' is out of the range of a float, expected a magnitude below 3.4e38", q.s);
    return obj_fail(r, "malformed number '%s', expected a decimal number such as -1.25e3", q.s);
}

// Up to `max` numbers from the rest of the line into v (all of them validated); *count gets how many there were.
bool obj_parse_numbers(obj_reporter *r, obj_cursor *c, float *v, int max, int *count) {
    const char *tok;
    size_t n;
    int k = 0;
    while (obj_next_token(c, &tok, &n)) {
        float f;
        decimal_status st = decimal_parse_float(tok, n, &f);
        if (st != DECIMAL_OK) return number_error(r, st, tok, n);
        if (k < max) v[k] = f;
        if (k < INT32_MAX) k++;
    }
    *count = k;
    return true;
}

// An integer index: [+-]digits, saturating far beyond the int32 range so that huge values are "out of range".
bool obj_parse_index(const char *s, size_t n, int64_t *out) {
    size_t i = 0;
    bool neg = false;
    if (n > 0 && (s[0] == '-' || s[0] == '+')) {
        neg = s[0] == '-';
        i = 1;
    }
    if (i == n) return false;
    int64_t v = 0;
    for (; i < n; i++) {
        if (!obj_is_digit(s[i])) return false;
        v = v < INT64_C(1000000000000000) ? v * 10 + (s[i] - '0') : INT64_C(1000000000000000);
    }
    *out = neg ? -v : v;
    return true;
}

char *obj_strdup_n(const char *s, size_t n) {
    char *d = malloc(n + 1);
    if (!d) return NULL;
    memcpy(d, s, n);
    d[n] = '\0';
    return d;
}

// ---------------------------------------------------------------------------------------------------------
// Files and paths

// dir + name (dir_len bytes of dir: the directory of the OBJ or MTL file), with the name's Windows separators
// turned into '/' and a leading "./" dropped; absolute names ('/' or '\\' first) are kept as they are.
char *obj_join_path(const char *dir, size_t dir_len, const char *name, size_t n) {
    bool windows_absolute = n > 0 && name[0] == '\\';
    while (!windows_absolute && n > 2 && name[0] == '.' && (name[1] == '/' || name[1] == '\\')) {
        name += 2; // "./x" is "x"
        n -= 2;
    }
    size_t d = windows_absolute || filepath_is_absolute(name, n) ? 0 : dir_len;
    char *p = filepath_join(dir, d, name, n);
    if (!p) return NULL;
    // By count, not up to a NUL: a malformed file may put NUL bytes in a name.
    for (size_t i = d; i < d + n; i++)
        if (p[i] == '\\') p[i] = '/';
    return p;
}

// A regular file of at most `max` bytes opened for reading; NULL on failure, with *errnum a filepath_problem
// value (EFBIG when the file is larger than max). *size gets its size.
FILE *obj_open_file(const char *path, size_t max, size_t *size, int *errnum) {
    struct stat st;
    *errnum = filepath_problem(path, &st);
    if (*errnum) return NULL;
    if ((unsigned long long)st.st_size > max) {
        *errnum = EFBIG;
        return NULL;
    }
    FILE *f = fopen(path, "rb");
    if (!f) *errnum = errno ? errno : EIO;
    *size = (size_t)st.st_size;
    return f;
}

// The whole of a regular file of at most `max` bytes, NUL-terminated; NULL on failure, with *errnum a
// filepath_problem value (ENOMEM when memory ran out, EFBIG when the file is larger than max).
char *obj_read_file(const char *path, size_t max, size_t *len, int *errnum) {
    size_t size;
    FILE *f = obj_open_file(path, max, &size, errnum);
    if (!f) return NULL;
    // The size is known: one allocation holds the file; should it grow meanwhile, it is read on up to max + 1 bytes.
    char *buf = file_read_stream(f, size, max, len, errnum);
    fclose(f);
    return buf;
}

// ---------------------------------------------------------------------------------------------------------
// Lines

bool obj_line_too_long(obj_reporter *rep, size_t length) {
    return obj_fail(rep, "line is %zu bytes long, expected at most %zu (%zu MiB)", length, (size_t)OBJ_MAX_LINE_BYTES,
                    (size_t)OBJ_MAX_LINE_BYTES >> 20);
}

// Reads the line that starts at s with fn(state, obj_cursor) after checking its length; *next gets the start of
// the next line.
bool obj_read_line(const char *s, const char *end, obj_reporter *rep, bool (*fn)(void *, obj_cursor *), void *state,
                   const char **next) {
    const char *nl = memchr(s, '\n', (size_t)(end - s));
    obj_cursor c = {s, nl ? nl : end};
    if ((size_t)(c.end - s) > OBJ_MAX_LINE_BYTES) return obj_line_too_long(rep, (size_t)(c.end - s));
    *next = nl ? nl + 1 : end;
    return fn(state, &c);
}

// Calls fn(state, obj_cursor) for every line of text, keeping rep->line current; stops at the first failure.
bool obj_for_each_line(const char *text, size_t length, obj_reporter *rep, bool (*fn)(void *, obj_cursor *),
                       void *state) {
    const char *s = text, *end = text + length;
    rep->line = 0;
    while (s < end) {
        rep->line++;
        if (!obj_read_line(s, end, rep, fn, state, &s)) return false;
    }
    return true;
}
