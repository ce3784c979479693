// obj_text.h — private to the OBJ and MTL readers (obj*.c, mtl.c): their text cut into lines and tokens, numbers
// and indices read from it, "file:line: ..." messages and warnings, names resolved against a file's directory.
#ifndef GLINT_OBJ_TEXT_H
#define GLINT_OBJ_TEXT_H

#include "core/status.h"
#include "io/obj.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#if defined(__GNUC__)
#define OBJ_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define OBJ_PRINTF(f, a)
#endif

/// Longest line of an OBJ or MTL file, in bytes (32 MiB): a face of OBJ_MAX_FACE_CORNERS (obj_parser.h) corners
/// written v/vt/vn with 8-digit indices fits.
#define OBJ_MAX_LINE_BYTES ((size_t)32 << 20)
/// Most elements of one kind (vertices, triangles, materials, ...) a file may define.
enum { OBJ_MAX_ELEMENTS = INT32_MAX };
/// Characters of a token quoted in a message; distinct unsupported keywords reported per file.
enum { OBJ_QUOTE_MAX = 40, OBJ_MAX_IGNORED_KEYWORDS = 16 };

/// Where messages go and what they are prefixed with; one per file being read.
typedef struct obj_reporter {
    const char *name;       ///< the file, as messages name it
    long line;              ///< the line being read (1-based)
    obj_warning_fn warn;    ///< NULL: warnings are only counted
    void *user;             ///< passed to warn
    glint_error *err;       ///< where a failure's message goes (may be NULL)
    size_t *warnings;       ///< counts every warning
    char ignored[OBJ_MAX_IGNORED_KEYWORDS][OBJ_QUOTE_MAX + 4]; ///< unsupported keywords reported so far
    int ignored_count;
    bool nomem; ///< the failure is running out of memory: a resource failure (GLINT_ERR_RENDER), not bad input
} obj_reporter;

/// A token fit for a message (see obj_quote).
typedef struct obj_quoted {
    char s[OBJ_QUOTE_MAX + 4];
} obj_quoted;

/// The rest of a line being read: [p, end), end at its '\n' or the end of the text.
typedef struct obj_cursor {
    const char *p, *end;
} obj_cursor;

/// Whether c is a blank within a line (not '\n').
static inline bool obj_is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
/// Whether c is a decimal digit.
static inline bool obj_is_digit(char c) { return c >= '0' && c <= '9'; }

/// The next whitespace-separated token; a token starting with '#' is a comment that ends the line.
static inline bool obj_next_token(obj_cursor *c, const char **tok, size_t *len) {
    const char *p = c->p;
    while (p < c->end && obj_is_space(*p)) p++;
    if (p == c->end || *p == '#') {
        c->p = c->end;
        return false;
    }
    const char *s = p;
    while (p < c->end && !obj_is_space(*p)) p++;
    *tok = s;
    *len = (size_t)(p - s);
    c->p = p;
    return true;
}

/// A token fit for a message: at most OBJ_QUOTE_MAX characters, anything unprintable shown as '?'.
obj_quoted obj_quote(const char *s, size_t n);
/// A file name fit for a message: as obj_quote(), but a long one keeps its end (the file name), not its start.
obj_quoted obj_quote_path(const char *s, size_t n);
/// Writes "file:line: " and the message into r->err; always false.
OBJ_PRINTF(2, 3) bool obj_fail(obj_reporter *r, const char *fmt, ...);
/// "file:line: out of memory"; the load then fails with GLINT_ERR_RENDER. Always false.
bool obj_out_of_memory(obj_reporter *r);
/// Counts a warning and passes "file:line: warning: ..." ("file: warning: ..." for line 0) to the callback.
OBJ_PRINTF(3, 4) void obj_warn_at(obj_reporter *r, long line, const char *fmt, ...);
/// Warns that statements `kw` are not supported, once per keyword and file (a file full of `l` lines warns once).
void obj_warn_unsupported(obj_reporter *r, const char *kw, size_t n);

/// The rest of the line without surrounding blanks and without a comment that starts after a blank.
void obj_rest_of_line(obj_cursor *c, const char **s, size_t *n);
/// Whether the token tok[0, n) is `word`.
bool obj_token_is(const char *tok, size_t n, const char *word);
/// Up to `max` numbers from the rest of the line into v (all of them validated); *count gets how many there were.
bool obj_parse_numbers(obj_reporter *r, obj_cursor *c, float *v, int max, int *count);
/// An integer index: [+-]digits, saturating far beyond the int32 range so that huge values are "out of range".
bool obj_parse_index(const char *s, size_t n, int64_t *out);
/// A NUL-terminated copy of s[0, n); NULL when memory runs out.
char *obj_strdup_n(const char *s, size_t n);

/// dir + name (dir_len bytes of dir: the directory of the OBJ or MTL file), with the name's Windows separators
/// turned into '/' and a leading "./" dropped; absolute names ('/' or '\\' first) are kept as they are.
char *obj_join_path(const char *dir, size_t dir_len, const char *name, size_t n);
/// A regular file of at most `max` bytes opened for reading; NULL on failure, with *errnum a filepath_problem
/// value (EFBIG when the file is larger than max). *size gets its size.
FILE *obj_open_file(const char *path, size_t max, size_t *size, int *errnum);
/// The whole of a regular file of at most `max` bytes, NUL-terminated; NULL on failure, with *errnum a
/// filepath_problem value (ENOMEM when memory ran out, EFBIG when the file is larger than max).
char *obj_read_file(const char *path, size_t max, size_t *len, int *errnum);

/// "file:line: line is N bytes long, expected at most ..."; always false.
bool obj_line_too_long(obj_reporter *rep, size_t length);
/// Reads the line that starts at s with fn(state, cursor) after checking its length; *next gets the start of
/// the next line.
bool obj_read_line(const char *s, const char *end, obj_reporter *rep, bool (*fn)(void *, obj_cursor *), void *state,
                   const char **next);
/// Calls fn(state, cursor) for every line of text, keeping rep->line current; stops at the first failure.
bool obj_for_each_line(const char *text, size_t length, obj_reporter *rep, bool (*fn)(void *, obj_cursor *),
                       void *state);

#endif
