// json_scan.c — strict JSON syntax check (RFC 8259) with a position index of every value and key.
// cJSON accepts more than JSON (leading zeros, raw control characters, "\u0000", any byte <= 32 as
// whitespace), stops at 1000 nesting levels and gives no line numbers; this pass runs first, so that
// every syntax error is precise and cJSON only ever sees text it reads the same way we do.
#include "io/json_scan.h"
#include "core/status.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct scanner {
    const unsigned char *s;
    size_t len;
    json_index *ix;
    json_scan_error *e;
} scanner;

/// An array or object whose closing bracket has not been read yet.
typedef struct open_container {
    uint32_t tok;
    size_t offset;
    bool object;
} open_container;

enum { SCAN_EXPECT_VALUE, SCAN_EXPECT_KEY, SCAN_AFTER_VALUE };
#define NO_COMMA ((size_t)-1)

static bool is_digit(int c) { return c >= '0' && c <= '9'; }
static bool is_ws(int c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
// Characters that continue a number or a bare word, so that "01", "1x" and "tru" are read whole.
static bool is_word(int c) {
    return is_digit(c) || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '+' || c == '-' ||
           c == '.';
}

static size_t skip_ws(const scanner *sc, size_t p) {
    while (p < sc->len && is_ws(sc->s[p])) p++;
    return p;
}

/// Length (2-4) of the well-formed UTF-8 sequence of a non-ASCII character at p, or 0 when malformed.
static size_t utf8_sequence(const unsigned char *s, size_t len, size_t p) {
    unsigned c = s[p], cp, min;
    size_t n;
    if (c >= 0xC2 && c <= 0xDF) { n = 2; cp = c & 0x1Fu; min = 0x80; }
    else if (c >= 0xE0 && c <= 0xEF) { n = 3; cp = c & 0x0Fu; min = 0x800; }
    else if (c >= 0xF0 && c <= 0xF4) { n = 4; cp = c & 0x07u; min = 0x10000; }
    else return 0;
    if (len - p < n) return 0;
    for (size_t i = 1; i < n; i++) {
        unsigned b = s[p + i];
        if ((b & 0xC0u) != 0x80u) return 0;
        cp = (cp << 6) | (b & 0x3Fu);
    }
    // Overlong forms, UTF-16 surrogates and code points beyond Unicode are not UTF-8.
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return n;
}

/// Whether code point cp shows as nothing or as a blank: no-break and typographic spaces, zero-width and
/// direction marks, line and paragraph separators, the soft hyphen and the word joiners.
static bool is_invisible(unsigned cp) {
    return cp == 0x00A0 || cp == 0x00AD || cp == 0x1680 || (cp >= 0x2000 && cp <= 0x200F) ||
           (cp >= 0x2028 && cp <= 0x202F) || (cp >= 0x205F && cp <= 0x2064) || cp == 0x3000;
}

/// Describes what stands at p for a "got ..." clause: a quoted word or character, or "end of file".
static const char *describe_at(const scanner *sc, size_t p, char *buf, size_t size) {
    if (p >= sc->len) return "end of file";
    unsigned c = sc->s[p];
    if (is_word((int)c)) {
        size_t n = 0;
        while (p + n < sc->len && n < 24 && is_word(sc->s[p + n])) n++;
        bool more = p + n < sc->len && is_word(sc->s[p + n]);
        snprintf(buf, size, "'%.*s%s'", (int)n, (const char *)sc->s + p, more ? "..." : "");
    } else if (c < 0x20 || c == 0x7F) {
        snprintf(buf, size, "control character U+%04X", c);
    } else if (c >= 0x80) {
        size_t n = utf8_sequence(sc->s, sc->len, p);
        unsigned cp = n ? c & (0x7Fu >> n) : 0;
        for (size_t i = 1; i < n; i++) cp = cp << 6 | (sc->s[p + i] & 0x3Fu);
        // Characters that print as nothing (or as a plain space) are named by their code point.
        if (cp == 0xFEFF) snprintf(buf, size, "byte-order mark U+FEFF");
        else if (n && cp < 0xA0) snprintf(buf, size, "control character U+%04X", cp);
        else if (n && is_invisible(cp)) snprintf(buf, size, "invisible character U+%04X", cp);
        else if (n) snprintf(buf, size, "'%.*s'", (int)n, (const char *)sc->s + p);
        else snprintf(buf, size, "byte 0x%02X (not UTF-8)", c);
    } else {
        snprintf(buf, size, "'%c'", (char)c);
    }
    return buf;
}

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static json_result scan_fail(scanner *sc, size_t offset, const char *fmt, ...) {
    sc->e->offset = offset;
    va_list ap;
    va_start(ap, fmt);
    status_vformat(sc->e->message, sizeof sc->e->message, "", fmt, ap);
    va_end(ap);
    return JSON_SCAN_SYNTAX;
}

// Appends a token; the caller sets `next` of containers when they close.
static json_result add_token(scanner *sc, json_kind kind, size_t offset) {
    json_index *ix = sc->ix;
    if (ix->count >= (size_t)JSON_MAX_VALUES)
        return scan_fail(sc, offset, "more than %d JSON values (keys included); glint reads at most that many",
                         JSON_MAX_VALUES);
    if (ix->count == ix->capacity) {
        size_t cap = ix->capacity ? ix->capacity * 2 : 256;
        json_token *t = realloc(ix->tok, cap * sizeof *t);
        if (!t) {
            snprintf(sc->e->message, sizeof sc->e->message, "out of memory");
            sc->e->offset = offset;
            return JSON_SCAN_NOMEM;
        }
        ix->tok = t;
        ix->capacity = cap;
    }
    json_token *t = &ix->tok[ix->count++];
    t->offset = (uint32_t)offset;
    t->next = (uint32_t)ix->count;
    t->kind = (uint8_t)kind;
    return JSON_SCAN_OK;
}

/// Value of the 4 hex digits at p, or -1.
static long hex4(const scanner *sc, size_t p) {
    if (p > sc->len || sc->len - p < 4) return -1;
    long v = 0;
    for (size_t i = 0; i < 4; i++) {
        int c = sc->s[p + i], d;
        if (is_digit(c)) d = c - '0';
        else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
        else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
        else return -1;
        v = v * 16 + d;
    }
    return v;
}

// Reads the string whose opening quote is at *pp; leaves *pp after the closing quote.
static json_result scan_string(scanner *sc, size_t *pp) {
    const unsigned char *s = sc->s;
    size_t start = *pp, p = start + 1;
    for (;;) {
        if (p >= sc->len) return scan_fail(sc, start, "unterminated string; expected a closing '\"'");
        unsigned c = s[p];
        if (c == '"') break;
        if (c == '\\') {
            if (p + 1 >= sc->len) return scan_fail(sc, start, "unterminated string; expected a closing '\"'");
            unsigned esc = s[p + 1];
            if (esc == '"' || esc == '\\' || esc == '/' || esc == 'b' || esc == 'f' || esc == 'n' || esc == 'r' ||
                esc == 't') {
                p += 2;
                continue;
            }
            if (esc != 'u') {
                char what[48];
                if (esc > 0x20 && esc < 0x7F) snprintf(what, sizeof what, "'\\%c'", (char)esc);
                else snprintf(what, sizeof what, "'\\' followed by byte 0x%02X", esc);
                return scan_fail(sc, p, "invalid escape %s in a string; expected one of %s", what,
                                 "\\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX");
            }
            long cp = hex4(sc, p + 2);
            if (cp < 0) return scan_fail(sc, p, "invalid escape: \\u must be followed by 4 hexadecimal digits");
            if (cp == 0) return scan_fail(sc, p, "\\u0000 (NUL) is not allowed in a string");
            if (cp >= 0xDC00 && cp <= 0xDFFF)
                return scan_fail(sc, p,
                                 "unpaired UTF-16 low surrogate \\u%04lX; it must follow a high surrogate "
                                 "\\uD800-\\uDBFF",
                                 cp);
            if (cp >= 0xD800 && cp <= 0xDBFF) {
                // A high surrogate needs its low half right after it, as cJSON decodes them as a pair.
                long low = (p + 7 < sc->len && s[p + 6] == '\\' && s[p + 7] == 'u') ? hex4(sc, p + 8) : -1;
                if (low < 0xDC00 || low > 0xDFFF)
                    return scan_fail(sc, p,
                                     "unpaired UTF-16 high surrogate \\u%04lX; expected a low surrogate "
                                     "\\uDC00-\\uDFFF after it",
                                     cp);
                p += 12;
                continue;
            }
            p += 6;
            continue;
        }
        if (c == '\n' || c == '\r')
            return scan_fail(sc, p,
                             "line break inside a string; expected a closing '\"' first (write \\n for a line break)");
        if (c == 0) return scan_fail(sc, p, "NUL byte inside a string; strings cannot contain U+0000");
        if (c < 0x20) return scan_fail(sc, p, "control character U+%04X inside a string; write it as \\u%04X", c, c);
        if (c < 0x80) {
            p++;
            continue;
        }
        size_t n = utf8_sequence(s, sc->len, p);
        if (!n) return scan_fail(sc, p, "invalid UTF-8 byte 0x%02X in a string; the file must be UTF-8", c);
        p += n;
    }
    *pp = p + 1;
    return JSON_SCAN_OK;
}

// Reads a number per the JSON grammar -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)? starting at *pp.
static json_result scan_number(scanner *sc, size_t *pp) {
    const unsigned char *s = sc->s;
    size_t len = sc->len, start = *pp, p = start;
    char buf[64];
    if (s[p] == '-') p++;
    if (p < len && s[p] == '0') p++;
    else if (p < len && is_digit(s[p])) while (p < len && is_digit(s[p])) p++;
    else goto bad;
    if (p < len && s[p] == '.') {
        p++;
        if (!(p < len && is_digit(s[p]))) goto bad;
        while (p < len && is_digit(s[p])) p++;
    }
    if (p < len && (s[p] == 'e' || s[p] == 'E')) {
        p++;
        if (p < len && (s[p] == '+' || s[p] == '-')) p++;
        if (!(p < len && is_digit(s[p]))) goto bad;
        while (p < len && is_digit(s[p])) p++;
    }
    if (p < len && is_word(s[p])) goto bad; // "01", "1.5.2", "2x"
    if (p - start > JSON_MAX_NUMBER_LENGTH)
        return scan_fail(sc, start, "number %s has %zu characters; at most %d are allowed",
                         describe_at(sc, start, buf, sizeof buf), p - start, JSON_MAX_NUMBER_LENGTH);
    *pp = p;
    return JSON_SCAN_OK;
bad:
    return scan_fail(sc, start, "invalid number %s; expected a JSON number such as 12, -0.5 or 6.02e23",
                     describe_at(sc, start, buf, sizeof buf));
}

// Reads true, false or null at *pp.
static json_result scan_literal(scanner *sc, size_t *pp, json_kind *kind) {
    static const struct { const char *word; json_kind kind; } lits[] = {
        {"true", JSON_TRUE}, {"false", JSON_FALSE}, {"null", JSON_NULL}};
    size_t p = *pp;
    for (size_t i = 0; i < sizeof lits / sizeof lits[0]; i++) {
        size_t n = strlen(lits[i].word);
        bool match = sc->len - p >= n && memcmp(sc->s + p, lits[i].word, n) == 0;
        if (match && !(p + n < sc->len && is_word(sc->s[p + n]))) {
            *pp = p + n;
            *kind = lits[i].kind;
            return JSON_SCAN_OK;
        }
    }
    char buf[64];
    return scan_fail(sc, p, "expected a value (object, array, string, number, true, false or null), got %s",
                     describe_at(sc, p, buf, sizeof buf));
}

// "after a member of the object opened at 3:5" for messages about an unclosed container.
static void describe_open(const scanner *sc, const open_container *oc, char *buf, size_t size) {
    size_t line, col;
    json_line_col((const char *)sc->s, sc->len, oc->offset, &line, &col);
    snprintf(buf, size, "%s of the %s opened at %zu:%zu", oc->object ? "a member" : "an element",
             oc->object ? "object" : "array", line, col);
}

static json_result scan_document(scanner *sc) {
    const unsigned char *s = sc->s;
    size_t len = sc->len, p = 0, comma = NO_COMMA;
    open_container stack[JSON_MAX_DEPTH];
    int depth = 0, state = SCAN_EXPECT_VALUE;
    char got[64], where[96];
    json_result r;
    if (len >= 3 && memcmp(s, "\xEF\xBB\xBF", 3) == 0) p = 3; // a UTF-8 byte-order mark may open the file
    for (;;) {
        p = skip_ws(sc, p);
        if (state == SCAN_EXPECT_VALUE) {
            if (p >= len && sc->ix->count == 0)
                return scan_fail(sc, 0, "the file %s; expected a JSON object",
                                 len ? "holds only white space" : "is empty");
            int c = p < len ? s[p] : -1;
            if (comma != NO_COMMA && c == ']')
                return scan_fail(sc, comma, "trailing comma before ']'; expected another value after ','");
            comma = NO_COMMA;
            if (c == '{' || c == '[') {
                if (depth == JSON_MAX_DEPTH)
                    return scan_fail(sc, p, "arrays and objects nested more than %d levels deep", JSON_MAX_DEPTH);
                if ((r = add_token(sc, c == '{' ? JSON_OBJECT : JSON_ARRAY, p)) != JSON_SCAN_OK) return r;
                stack[depth++] = (open_container){(uint32_t)(sc->ix->count - 1), p, c == '{'};
                p = skip_ws(sc, p + 1);
                if (p < len && s[p] == (c == '{' ? '}' : ']')) {
                    sc->ix->tok[stack[--depth].tok].next = (uint32_t)sc->ix->count;
                    p++;
                    state = SCAN_AFTER_VALUE;
                } else {
                    state = c == '{' ? SCAN_EXPECT_KEY : SCAN_EXPECT_VALUE;
                }
                continue;
            }
            if (c == '"') {
                if ((r = add_token(sc, JSON_STRING, p)) != JSON_SCAN_OK) return r;
                if ((r = scan_string(sc, &p)) != JSON_SCAN_OK) return r;
            } else if (c == '-' || is_digit(c)) {
                if ((r = add_token(sc, JSON_NUMBER, p)) != JSON_SCAN_OK) return r;
                if ((r = scan_number(sc, &p)) != JSON_SCAN_OK) return r;
            } else if (c == 't' || c == 'f' || c == 'n') {
                json_kind kind = JSON_NULL;
                size_t at = p;
                if ((r = scan_literal(sc, &p, &kind)) != JSON_SCAN_OK) return r;
                if ((r = add_token(sc, kind, at)) != JSON_SCAN_OK) return r;
            } else {
                return scan_fail(sc, p, "expected a value (object, array, string, number, true, false or null), got %s",
                                 describe_at(sc, p, got, sizeof got));
            }
            state = SCAN_AFTER_VALUE;
        } else if (state == SCAN_EXPECT_KEY) {
            int c = p < len ? s[p] : -1;
            if (c != '"') {
                if (comma != NO_COMMA && c == '}')
                    return scan_fail(sc, comma, "trailing comma before '}'; expected another key after ','");
                return scan_fail(sc, p, "expected a key in double quotes%s, got %s", comma == NO_COMMA ? " or '}'" : "",
                                 describe_at(sc, p, got, sizeof got));
            }
            size_t key = p;
            if ((r = add_token(sc, JSON_STRING, p)) != JSON_SCAN_OK) return r;
            if ((r = scan_string(sc, &p)) != JSON_SCAN_OK) return r;
            size_t key_len = p - key;
            p = skip_ws(sc, p);
            if (p >= len || s[p] != ':')
                return scan_fail(sc, p, "expected ':' after the key %.*s%s, got %s", (int)(key_len > 40 ? 40 : key_len),
                                 (const char *)s + key, key_len > 40 ? "...\"" : "",
                                 describe_at(sc, p, got, sizeof got));
            p++;
            comma = NO_COMMA;
            state = SCAN_EXPECT_VALUE;
        } else { // SCAN_AFTER_VALUE
            if (depth == 0) {
                if (p < len)
                    return scan_fail(sc, p, "unexpected %s after the end of the top-level value; expected end of file",
                                     describe_at(sc, p, got, sizeof got));
                return JSON_SCAN_OK;
            }
            const open_container *top = &stack[depth - 1];
            char close = top->object ? '}' : ']';
            if (p < len && s[p] == ',') {
                comma = p++;
                state = top->object ? SCAN_EXPECT_KEY : SCAN_EXPECT_VALUE;
            } else if (p < len && s[p] == close) {
                sc->ix->tok[top->tok].next = (uint32_t)sc->ix->count;
                depth--;
                p++;
            } else {
                describe_open(sc, top, where, sizeof where);
                return scan_fail(sc, p, "expected ',' or '%c' after %s, got %s", close, where,
                                 describe_at(sc, p, got, sizeof got));
            }
        }
    }
}

json_result json_scan(const char *text, size_t len, json_index *ix, json_scan_error *e) {
    memset(ix, 0, sizeof *ix);
    e->offset = 0;
    e->message[0] = '\0';
    scanner sc = {(const unsigned char *)text, text ? len : 0, ix, e};
    json_result r;
    if (sc.len >= UINT32_MAX) {
        snprintf(e->message, sizeof e->message, "the file is too large for the JSON reader (4 GiB or more)");
        r = JSON_SCAN_SYNTAX;
    } else {
        r = scan_document(&sc);
    }
    if (r != JSON_SCAN_OK) json_index_free(ix);
    return r;
}

void json_index_free(json_index *ix) {
    free(ix->tok);
    memset(ix, 0, sizeof *ix);
}

void json_line_col(const char *text, size_t len, size_t offset, size_t *line, size_t *col) {
    const unsigned char *s = (const unsigned char *)text;
    size_t l = 1, c = 1, i = 0;
    if (offset > len) offset = len;
    if (len >= 3 && offset >= 3 && memcmp(s, "\xEF\xBB\xBF", 3) == 0) i = 3; // editors do not show the BOM
    for (; i < offset; i++) {
        if (s[i] == '\n') {
            l++;
            c = 1;
        } else if ((s[i] & 0xC0u) != 0x80u) {
            c++; // count characters, not UTF-8 continuation bytes
        }
    }
    *line = l;
    *col = c;
}
