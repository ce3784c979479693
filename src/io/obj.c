// obj.c — the OBJ/MTL reader: one pass over the text (an OBJ file read in blocks), no allocation per line, plain
// v/vn/vt/f lines read by fast paths, faces triangulated as read.
#include "io/obj.h"
#include "core/array.h"
#include "core/file_read.h"
#include "core/filepath.h"
#include "core/prefetch.h"
#include "core/strmap.h"
#include "core/thread_pool.h"
#include "io/decimal.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#if defined(__GNUC__)
#define PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define PRINTF_LIKE(f, a)
#endif

enum { MAX_ELEMENTS = INT32_MAX, QUOTE_MAX = 40, MAX_IGNORED_KEYWORDS = 16 };
/// Bytes of an OBJ file read at a time: small enough to stay in the cache while it is parsed.
enum { OBJ_READ_BLOCK = 256 << 10 };

// ---------------------------------------------------------------------------------------------------------
// Messages

/// Where messages go and what they are prefixed with; one per file being read.
typedef struct reporter {
    const char *name;
    long line;
    const obj_options *opt;
    glint_error *err;
    size_t *warnings;
    char ignored[MAX_IGNORED_KEYWORDS][QUOTE_MAX + 4];
    int ignored_count;
    bool nomem; // the failure is running out of memory: a resource failure (GLINT_ERR_RENDER), not bad input
} reporter;

typedef struct quoted {
    char s[QUOTE_MAX + 4];
} quoted;

// A token fit for a message: at most QUOTE_MAX characters, anything unprintable shown as '?'.
static quoted quote(const char *s, size_t n) {
    quoted q;
    size_t k = 0;
    for (size_t i = 0; i < n && k < QUOTE_MAX; i++) {
        unsigned char c = (unsigned char)s[i];
        q.s[k++] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    if (n > QUOTE_MAX) {
        memcpy(q.s + k, "...", 3);
        k += 3;
    }
    q.s[k] = '\0';
    return q;
}

// A file name fit for a message: as quote(), but a long one keeps its end (the file name), not its start.
static quoted quote_path(const char *s, size_t n) {
    if (n <= QUOTE_MAX) return quote(s, n);
    quoted tail = quote(s + n - QUOTE_MAX, QUOTE_MAX), q;
    memcpy(q.s, "...", 3);
    memcpy(q.s + 3, tail.s, QUOTE_MAX + 1);
    return q;
}

PRINTF_LIKE(2, 3)
static bool fail(reporter *r, const char *fmt, ...) {
    if (!r->err) return false;
    int k = snprintf(r->err->message, sizeof r->err->message, "%s:%ld: ", r->name, r->line);
    if (k < 0 || (size_t)k >= sizeof r->err->message) return false;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err->message + k, sizeof r->err->message - (size_t)k, fmt, ap);
    va_end(ap);
    return false;
}

// "file:line: out of memory"; the load then fails with GLINT_ERR_RENDER.
static bool out_of_memory(reporter *r) {
    r->nomem = true;
    return fail(r, "out of memory");
}

PRINTF_LIKE(3, 4)
static void warn_at(reporter *r, long line, const char *fmt, ...) {
    (*r->warnings)++;
    if (!r->opt || !r->opt->warn) return;
    char buf[1200];
    int k = line > 0 ? snprintf(buf, sizeof buf, "%s:%ld: warning: ", r->name, line)
                     : snprintf(buf, sizeof buf, "%s: warning: ", r->name);
    if (k < 0 || (size_t)k >= sizeof buf) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf + k, sizeof buf - (size_t)k, fmt, ap);
    va_end(ap);
    r->opt->warn(buf, r->opt->user);
}

// Unsupported statements are reported once per keyword and file, so a file full of `l` lines warns once.
static void warn_unsupported(reporter *r, const char *kw, size_t n) {
    quoted q = quote(kw, n);
    for (int i = 0; i < r->ignored_count; i++)
        if (strcmp(r->ignored[i], q.s) == 0) return;
    if (r->ignored_count == MAX_IGNORED_KEYWORDS) return;
    memcpy(r->ignored[r->ignored_count++], q.s, sizeof q.s);
    warn_at(r, r->line, "'%s' statements are not supported; ignored (reported once)", q.s);
}

// ---------------------------------------------------------------------------------------------------------
// Tokens and numbers

typedef struct cursor {
    const char *p, *end;
} cursor;

static inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
static inline bool is_digit(char c) { return c >= '0' && c <= '9'; }

// The next whitespace-separated token; a token starting with '#' is a comment that ends the line.
static inline bool next_token(cursor *c, const char **tok, size_t *len) {
    const char *p = c->p;
    while (p < c->end && is_space(*p)) p++;
    if (p == c->end || *p == '#') {
        c->p = c->end;
        return false;
    }
    const char *s = p;
    while (p < c->end && !is_space(*p)) p++;
    *tok = s;
    *len = (size_t)(p - s);
    c->p = p;
    return true;
}

// The rest of the line without surrounding blanks and without a comment that starts after a blank.
static void rest_of_line(cursor *c, const char **s, size_t *n) {
    const char *p = c->p;
    while (p < c->end && is_space(*p)) p++;
    const char *start = p, *stop = c->end;
    if (p < c->end && *p == '#') stop = p;
    for (const char *q = p + 1; q < c->end && stop == c->end; q++)
        if (*q == '#' && is_space(q[-1])) stop = q;
    while (stop > start && is_space(stop[-1])) stop--;
    *s = start;
    *n = (size_t)(stop - start);
    c->p = c->end;
}

static bool token_is(const char *tok, size_t n, const char *word) {
    size_t k = strlen(word);
    return n == k && memcmp(tok, word, k) == 0;
}

static bool number_error(reporter *r, decimal_status st, const char *tok, size_t n) {
    if (st == DECIMAL_NOMEM) return out_of_memory(r);
    quoted q = quote(tok, n);
    if (st == DECIMAL_NOT_FINITE) return fail(r, "'%s' is not a finite number, expected a decimal number", q.s);
    if (st == DECIMAL_RANGE) return fail(r, "number '%s' is out of the range of a float, expected a magnitude below 3.4e38", q.s);
    return fail(r, "malformed number '%s', expected a decimal number such as -1.25e3", q.s);
}

// Up to `max` numbers from the rest of the line into v (all of them validated); *count gets how many there were.
static bool parse_numbers(reporter *r, cursor *c, float *v, int max, int *count) {
    const char *tok;
    size_t n;
    int k = 0;
    while (next_token(c, &tok, &n)) {
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
static bool parse_index(const char *s, size_t n, int64_t *out) {
    size_t i = 0;
    bool neg = false;
    if (n > 0 && (s[0] == '-' || s[0] == '+')) {
        neg = s[0] == '-';
        i = 1;
    }
    if (i == n) return false;
    int64_t v = 0;
    for (; i < n; i++) {
        if (!is_digit(s[i])) return false;
        v = v < INT64_C(1000000000000000) ? v * 10 + (s[i] - '0') : INT64_C(1000000000000000);
    }
    *out = neg ? -v : v;
    return true;
}

// ---------------------------------------------------------------------------------------------------------
// Strings

static char *dup_n(const char *s, size_t n) {
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
static char *join_path(const char *dir, size_t dir_len, const char *name, size_t n) {
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
static FILE *open_file(const char *path, size_t max, size_t *size, int *errnum) {
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
static char *read_file(const char *path, size_t max, size_t *len, int *errnum) {
    size_t size;
    FILE *f = open_file(path, max, &size, errnum);
    if (!f) return NULL;
    // The size is known: one allocation holds the file; should it grow meanwhile, it is read on up to max + 1 bytes.
    char *buf = file_read_stream(f, size, max, len, errnum);
    fclose(f);
    return buf;
}

// ---------------------------------------------------------------------------------------------------------
// MTL

/// What one `newmtl` block said, before it is mapped to a glint material.
typedef struct mtl_block {
    char *name;
    size_t name_len;
    long line;
    bool has_kd, has_ks, has_ke, has_ns, has_ni, has_d, has_tr, has_tf;
    vec3 kd, ks, ke, tf;
    float ns, ni, d, tr;
    int illum;
    char *map_kd;
    bool duplicate; // the name was defined before: the block is read (and checked) but dropped
} mtl_block;

static float max3(vec3 v) { return fmaxf(v.x, fmaxf(v.y, v.z)); }
static float clamp01(float x) { return fminf(1.0f, fmaxf(0.0f, x)); }
static vec3 clamp01v(vec3 v) { return v3(clamp01(v.x), clamp01(v.y), clamp01(v.z)); }

// The documented MTL -> glint mapping (see obj.h).
static material mtl_to_material(const mtl_block *b) {
    if (b->has_ke && max3(b->ke) > 0.0f) {
        material m = material_default(MAT_DIFFUSE_LIGHT);
        m.emission = b->ke;
        return m;
    }
    bool transparent = b->has_d ? b->d < 1.0f : (b->has_tr && b->tr > 0.0f);
    if (b->illum == 4 || b->illum == 6 || b->illum == 7 || b->illum == 9) transparent = true;
    if (transparent) {
        material m = material_default(MAT_DIELECTRIC);
        if (b->has_ni && b->ni > 0.0f) m.ior = b->ni;
        if (b->has_tf) m.albedo = clamp01v(b->tf);
        return m;
    }
    vec3 kd = b->has_kd ? b->kd : v3s(0.5f);
    if ((b->illum == 3 || b->illum == 5 || b->illum == 8) && b->has_ks && max3(b->ks) >= 0.25f &&
        max3(b->ks) >= max3(kd)) {
        material m = material_default(MAT_METAL);
        m.albedo = clamp01v(b->ks);
        // A Phong exponent n corresponds to a Beckmann roughness of about sqrt(2 / (n + 2)).
        m.fuzz = b->has_ns ? clamp01(sqrtf(2.0f / (b->ns + 2.0f))) : 0.0f;
        return m;
    }
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = kd;
    return m;
}

typedef struct mtl_parser {
    reporter rep;
    const char *dir; // the MTL file's name: its first dir_len bytes are its directory
    size_t dir_len;
    obj_material *out;
    size_t count, cap;
    strmap names; // material name -> index in out
    mtl_block cur;
    bool in_block;
} mtl_parser;

// Ends the current newmtl block: maps it and appends it (a repeated name keeps the first definition).
static bool mtl_finish_block(mtl_parser *ps) {
    if (!ps->in_block) return true;
    ps->in_block = false;
    mtl_block *b = &ps->cur;
    if (b->duplicate) {
        free(b->name);
        free(b->map_kd);
        return true;
    }
    if (ps->count >= MAX_ELEMENTS || !array_reserve((void **)&ps->out, &ps->cap, ps->count + 1, sizeof *ps->out)) {
        free(b->name);
        free(b->map_kd);
        return out_of_memory(&ps->rep);
    }
    obj_material *m = &ps->out[ps->count];
    m->name = b->name;
    m->defined = true;
    m->mat = mtl_to_material(b);
    m->diffuse_map = b->map_kd;
    m->line = b->line;
    if (!strmap_put(&ps->names, m->name, b->name_len, ps->count)) {
        m->name = NULL;
        free(b->name);
        free(b->map_kd);
        return out_of_memory(&ps->rep);
    }
    ps->count++;
    return true;
}

// `Kd r [g b]` (g = b = r when only r is given); components must be finite and >= 0.
static bool mtl_color(mtl_parser *ps, cursor *c, const char *kw, vec3 *out, bool *has) {
    cursor peek = *c;
    const char *tok;
    size_t n;
    if (next_token(&peek, &tok, &n) && (token_is(tok, n, "spectral") || token_is(tok, n, "xyz"))) {
        char what[32];
        snprintf(what, sizeof what, "%s %s", kw, token_is(tok, n, "xyz") ? "xyz" : "spectral");
        warn_unsupported(&ps->rep, what, strlen(what));
        return true;
    }
    float v[3];
    int count;
    if (!parse_numbers(&ps->rep, c, v, 3, &count)) return false;
    if (count != 1 && count != 3) return fail(&ps->rep, "'%s' has %d numbers, expected r g b", kw, count);
    if (count == 1) v[1] = v[2] = v[0];
    for (int i = 0; i < 3; i++)
        if (v[i] < 0.0f) return fail(&ps->rep, "'%s' has a negative component %g, expected values >= 0", kw, (double)v[i]);
    *out = v3(v[0], v[1], v[2]);
    *has = true;
    return true;
}

// One number in [lo, hi].
static bool mtl_scalar(mtl_parser *ps, cursor *c, const char *kw, float lo, float hi, float *out, bool *has) {
    float v[1];
    int count;
    if (!parse_numbers(&ps->rep, c, v, 1, &count)) return false;
    if (count != 1) return fail(&ps->rep, "'%s' has %d numbers, expected 1", kw, count);
    if (!(v[0] >= lo && v[0] <= hi)) {
        if (hi == INFINITY) return fail(&ps->rep, "'%s' is %g, expected a value >= %g", kw, (double)v[0], (double)lo);
        return fail(&ps->rep, "'%s' is %g, expected a value from %g to %g", kw, (double)v[0], (double)lo, (double)hi);
    }
    *out = v[0];
    *has = true;
    return true;
}

// `map_Kd [-options] file`: skips the options, resolves the file relative to the MTL's directory.
static bool mtl_map_kd(mtl_parser *ps, cursor *c) {
    static const struct { const char *name; int args; } options[] = {
        {"-blendu", 1}, {"-blendv", 1}, {"-cc", 1}, {"-clamp", 1}, {"-bm", 1}, {"-boost", 1}, {"-texres", 1},
        {"-imfchan", 1}, {"-type", 1}, {"-mm", 2}, {"-o", -3}, {"-s", -3}, {"-t", -3},
    };
    for (;;) {
        cursor peek = *c;
        const char *tok;
        size_t n;
        if (!next_token(&peek, &tok, &n) || tok[0] != '-') break;
        int args = 0;
        for (size_t i = 0; i < sizeof options / sizeof options[0]; i++)
            if (token_is(tok, n, options[i].name)) args = options[i].args;
        if (args == 0) break; // not an option: a file name that starts with '-'
        *c = peek;
        // -o, -s, -t take one to three numbers: take those that parse.
        for (int k = 0; k < (args < 0 ? -args : args); k++) {
            cursor arg = *c;
            float f;
            if (!next_token(&arg, &tok, &n)) break;
            if (args < 0 && k > 0 && decimal_parse_float(tok, n, &f) != DECIMAL_OK) break;
            *c = arg;
        }
    }
    const char *file;
    size_t n;
    rest_of_line(c, &file, &n);
    if (n == 0) return fail(&ps->rep, "'map_Kd' needs a file name");
    char *path = join_path(ps->dir, ps->dir_len, file, n);
    if (!path) return out_of_memory(&ps->rep);
    if (!ps->rep.opt || !ps->rep.opt->skip_files) {
        struct stat st;
        int e = filepath_problem(path, &st);
        if (e) {
            // Exporters on Windows write absolute paths: try the bare file name next to the MTL file.
            const char *slash = strrchr(path, '/');
            char *alt = slash ? join_path(ps->dir, ps->dir_len, slash + 1, strlen(slash + 1)) : NULL;
            if (alt && filepath_problem(alt, &st) == 0) {
                free(path);
                path = alt;
            } else {
                free(alt);
                warn_at(&ps->rep, ps->rep.line, "texture '%s' not found (%s); material '%s' uses its Kd colour",
                        quote_path(file, n).s, filepath_problem_text(e), quote(ps->cur.name, ps->cur.name_len).s);
                free(path);
                return true;
            }
        }
    }
    free(ps->cur.map_kd);
    ps->cur.map_kd = path;
    return true;
}

static bool mtl_statement(mtl_parser *ps, cursor *c) {
    const char *kw;
    size_t kn;
    if (!next_token(c, &kw, &kn)) return true;
    if (token_is(kw, kn, "newmtl")) {
        if (!mtl_finish_block(ps)) return false;
        const char *name;
        size_t n;
        rest_of_line(c, &name, &n);
        if (n == 0) return fail(&ps->rep, "'newmtl' needs a material name");
        memset(&ps->cur, 0, sizeof ps->cur);
        ps->cur.name = dup_n(name, n);
        if (!ps->cur.name) return out_of_memory(&ps->rep);
        ps->cur.name_len = n;
        ps->cur.line = ps->rep.line;
        ps->cur.illum = -1;
        ps->in_block = true;
        if (strmap_get(&ps->names, name, n, NULL)) {
            ps->cur.duplicate = true;
            warn_at(&ps->rep, ps->rep.line, "material '%s' is defined again; the first definition is used",
                    quote(name, n).s);
        }
        return true;
    }
    static const char *const ignored[] = {
        "map_Ka", "map_Ks", "map_Ns", "map_d", "map_Tr", "map_bump", "map_Bump", "bump", "disp", "decal", "refl",
        "map_Ke", "map_Pr", "map_Pm", "map_Ps", "norm", "map_refl", "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso",
        "anisor", "sharpness", "map_aat",
    };
    static const char *const known[] = {"Kd", "Ks", "Ke", "Ka", "Tf", "Ns", "Ni", "d", "Tr", "illum", "map_Kd"};
    bool is_known = false;
    for (size_t i = 0; i < sizeof known / sizeof known[0] && !is_known; i++) is_known = token_is(kw, kn, known[i]);
    for (size_t i = 0; i < sizeof ignored / sizeof ignored[0] && !is_known; i++)
        if (token_is(kw, kn, ignored[i])) is_known = true;
    if (!is_known) {
        warn_unsupported(&ps->rep, kw, kn);
        return true;
    }
    if (!ps->in_block) return fail(&ps->rep, "'%s' before any 'newmtl', expected 'newmtl name' first", quote(kw, kn).s);
    mtl_block *b = &ps->cur;
    vec3 unused;
    bool unused_flag;
    if (token_is(kw, kn, "Kd")) return mtl_color(ps, c, "Kd", &b->kd, &b->has_kd);
    if (token_is(kw, kn, "Ks")) return mtl_color(ps, c, "Ks", &b->ks, &b->has_ks);
    if (token_is(kw, kn, "Ke")) return mtl_color(ps, c, "Ke", &b->ke, &b->has_ke);
    if (token_is(kw, kn, "Tf")) return mtl_color(ps, c, "Tf", &b->tf, &b->has_tf);
    if (token_is(kw, kn, "Ka")) return mtl_color(ps, c, "Ka", &unused, &unused_flag);
    if (token_is(kw, kn, "Ns")) return mtl_scalar(ps, c, "Ns", 0.0f, INFINITY, &b->ns, &b->has_ns);
    if (token_is(kw, kn, "Ni")) return mtl_scalar(ps, c, "Ni", 0.0f, INFINITY, &b->ni, &b->has_ni);
    if (token_is(kw, kn, "Tr")) return mtl_scalar(ps, c, "Tr", 0.0f, 1.0f, &b->tr, &b->has_tr);
    if (token_is(kw, kn, "d")) {
        cursor peek = *c;
        const char *tok;
        size_t n;
        if (next_token(&peek, &tok, &n) && token_is(tok, n, "-halo")) *c = peek;
        return mtl_scalar(ps, c, "d", 0.0f, 1.0f, &b->d, &b->has_d);
    }
    if (token_is(kw, kn, "illum")) {
        const char *tok;
        size_t n;
        int64_t v;
        if (!next_token(c, &tok, &n)) return fail(&ps->rep, "'illum' needs an illumination model, expected an integer from 0 to 10");
        if (!parse_index(tok, n, &v) || v < 0 || v > 10)
            return fail(&ps->rep, "'illum' is '%s', expected an integer from 0 to 10", quote(tok, n).s);
        if (next_token(c, &tok, &n)) return fail(&ps->rep, "'illum' has more than one value, expected an integer from 0 to 10");
        b->illum = (int)v;
        return true;
    }
    if (token_is(kw, kn, "map_Kd")) return mtl_map_kd(ps, c);
    return true; // accepted and ignored
}

static bool line_too_long(reporter *rep, size_t length) {
    return fail(rep, "line is %zu bytes long, expected at most %zu (%zu MiB)", length, (size_t)OBJ_MAX_LINE_BYTES,
                (size_t)OBJ_MAX_LINE_BYTES >> 20);
}

// Reads the line that starts at s with fn(state, cursor) after checking its length; *next gets the start of
// the next line.
static bool read_line(const char *s, const char *end, reporter *rep, bool (*fn)(void *, cursor *), void *state,
                      const char **next) {
    const char *nl = memchr(s, '\n', (size_t)(end - s));
    cursor c = {s, nl ? nl : end};
    if ((size_t)(c.end - s) > OBJ_MAX_LINE_BYTES) return line_too_long(rep, (size_t)(c.end - s));
    *next = nl ? nl + 1 : end;
    return fn(state, &c);
}

// Calls fn(state, cursor) for every line of text, keeping rep->line current; stops at the first failure.
static bool for_each_line(const char *text, size_t length, reporter *rep, bool (*fn)(void *, cursor *), void *state) {
    const char *s = text, *end = text + length;
    rep->line = 0;
    while (s < end) {
        rep->line++;
        if (!read_line(s, end, rep, fn, state, &s)) return false;
    }
    return true;
}

static bool mtl_line(void *state, cursor *c) { return mtl_statement(state, c); }

void obj_materials_free(obj_material *m, size_t count) {
    if (!m) return;
    for (size_t i = 0; i < count; i++) {
        free(m[i].name);
        free(m[i].diffuse_map);
    }
    free(m);
}

// Parses an MTL text; warnings are added to *warnings.
static glint_status mtl_parse_counted(const char *name, const char *text, size_t length, const obj_options *opt,
                                      obj_material **out, size_t *count, size_t *warnings, glint_error *err) {
    mtl_parser ps;
    memset(&ps, 0, sizeof ps);
    ps.rep.name = name;
    ps.rep.opt = opt;
    ps.rep.err = err;
    ps.rep.warnings = warnings;
    ps.dir = name;
    ps.dir_len = filepath_dir_length(name);
    bool ok = for_each_line(text, length, &ps.rep, mtl_line, &ps) && mtl_finish_block(&ps);
    if (ps.in_block) { // a failure inside a block
        free(ps.cur.name);
        free(ps.cur.map_kd);
    }
    strmap_free(&ps.names);
    if (!ok) {
        obj_materials_free(ps.out, ps.count);
        *out = NULL;
        *count = 0;
        return ps.rep.nomem ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    *out = ps.out;
    *count = ps.count;
    return GLINT_OK;
}

glint_status mtl_parse(const char *name, const char *text, size_t length, const obj_options *opt,
                       obj_material **out, size_t *count, glint_error *err) {
    size_t warnings = 0;
    return mtl_parse_counted(name, text, length, opt, out, count, &warnings, err);
}

// ---------------------------------------------------------------------------------------------------------
// OBJ

typedef struct corner {
    int32_t v, t, n;
} corner;

/// Triangles the fast path has read and not yet added, so that their corners' positions, far apart in a
/// large mesh, reach the cache while the next lines are read.
enum { QUEUED_TRIANGLES = 8 };

typedef struct queued_triangle {
    corner k[3];
    long line;
} queued_triangle;

typedef struct obj_parser {
    reporter rep;
    obj_model *model;
    const obj_options *opt;
    size_t pos_cap, nrm_cap, uv_cap, tri_cap, slot_cap;
    size_t nrm_corner_cap, uv_corner_cap; // of the mesh's normal_corners and uv_corners
    corner *corners;
    size_t corner_cap;
    double *px, *py;  // a face projected on its plane, for triangulation
    int *next, *prev; // the remaining polygon while ear clipping
    size_t scratch_cap;
    int32_t material; // current slot, -1 before any usemtl
    strmap slots; // material name -> slot in model->materials
    obj_material *defs; // everything the material libraries define
    size_t def_count, def_cap;
    strmap def_names; // material name -> index in defs
    char **libs; // libraries read so far, so that a repeated mtllib is read once
    size_t lib_count, lib_cap;
    const char *dir; // the OBJ file's name: its first dir_len bytes are its directory
    size_t dir_len;
    long first_zero_line;
    bool warned_fan, warned_bad_polygon;
    queued_triangle queue[QUEUED_TRIANGLES]; // a ring, oldest at queue_head
    int queue_head, queue_count;
} obj_parser;

static bool too_many(reporter *r, const char *what) {
    return fail(r, "too many %s, expected at most %d", what, MAX_ELEMENTS);
}

// Stores a position, a normal, a texture coordinate: the last step of both the statements and the fast paths.
static bool add_position(obj_parser *ps, const float *v) {
    mesh *m = &ps->model->mesh;
    if (m->position_count >= MAX_ELEMENTS) return too_many(&ps->rep, "vertices");
    if (m->position_count == ps->pos_cap &&
        !array_reserve((void **)&m->positions, &ps->pos_cap, m->position_count + 1, sizeof *m->positions))
        return out_of_memory(&ps->rep);
    m->positions[m->position_count++] = v3(v[0], v[1], v[2]);
    return true;
}

static bool add_normal(obj_parser *ps, const float *v) {
    mesh *m = &ps->model->mesh;
    if (m->normal_count >= MAX_ELEMENTS) return too_many(&ps->rep, "normals");
    if (m->normal_count == ps->nrm_cap &&
        !array_reserve((void **)&m->normals, &ps->nrm_cap, m->normal_count + 1, sizeof *m->normals))
        return out_of_memory(&ps->rep);
    m->normals[m->normal_count++] = v3(v[0], v[1], v[2]);
    return true;
}

static bool add_texcoord(obj_parser *ps, const float *v, int count) {
    mesh *m = &ps->model->mesh;
    if (m->uv_count >= MAX_ELEMENTS) return too_many(&ps->rep, "texture coordinates");
    if (m->uv_count == ps->uv_cap && !array_reserve((void **)&m->uvs, &ps->uv_cap, m->uv_count + 1, sizeof *m->uvs))
        return out_of_memory(&ps->rep);
    m->uvs[m->uv_count++] = (uv2){v[0], count > 1 ? v[1] : 0.0f};
    return true;
}

static bool obj_vertex(obj_parser *ps, cursor *c) {
    float v[7];
    int count;
    if (!parse_numbers(&ps->rep, c, v, 7, &count)) return false;
    if (count < 3 || count > 7) return fail(&ps->rep, "'v' has %d numbers, expected 3 (x y z) to 7", count);
    return add_position(ps, v);
}

static bool obj_normal(obj_parser *ps, cursor *c) {
    float v[3];
    int count;
    if (!parse_numbers(&ps->rep, c, v, 3, &count)) return false;
    if (count != 3) return fail(&ps->rep, "'vn' has %d numbers, expected 3 (x y z)", count);
    return add_normal(ps, v);
}

static bool obj_texcoord(obj_parser *ps, cursor *c) {
    float v[3] = {0, 0, 0};
    int count;
    if (!parse_numbers(&ps->rep, c, v, 3, &count)) return false;
    if (count < 1 || count > 3) return fail(&ps->rep, "'vt' has %d numbers, expected 1 to 3 (u [v [w]])", count);
    return add_texcoord(ps, v, count);
}

// A 1-based or negative (relative) index into `count` elements -> 0-based.
static bool resolve_index(obj_parser *ps, const char *tok, size_t n, int64_t idx, size_t count, const char *what,
                          const char *plural, int32_t *out) {
    if (idx > 0 && (uint64_t)idx <= count) {
        *out = (int32_t)(idx - 1);
        return true;
    }
    if (idx < 0 && (uint64_t)(-idx) <= count) {
        *out = (int32_t)((int64_t)count + idx);
        return true;
    }
    quoted q = quote(tok, n);
    if (count == 0) return fail(&ps->rep, "%s index %s out of range, no %s defined before this face", what, q.s, plural);
    return fail(&ps->rep, "%s index %s out of range, expected 1..%zu or -%zu..-1", what, q.s, count, count);
}

// One face corner: v, v/vt, v//vn or v/vt/vn.
static bool parse_corner(obj_parser *ps, const char *tok, size_t n, corner *out) {
    const mesh *m = &ps->model->mesh;
    const char *s1 = memchr(tok, '/', n);
    const char *s2 = s1 ? memchr(s1 + 1, '/', (size_t)(tok + n - s1 - 1)) : NULL;
    const char *vs = tok, *ts = NULL, *ns = NULL;
    size_t vl = s1 ? (size_t)(s1 - tok) : n, tl = 0, nl = 0;
    bool ok = true;
    if (s1 && !s2) {
        ts = s1 + 1;
        tl = (size_t)(tok + n - ts);
        ok = tl > 0;
    } else if (s2) {
        ts = s1 + 1;
        tl = (size_t)(s2 - ts);
        ns = s2 + 1;
        nl = (size_t)(tok + n - ns);
        ok = nl > 0 && !memchr(ns, '/', nl);
    }
    int64_t vi = 0, ti = 0, ni = 0;
    ok = ok && parse_index(vs, vl, &vi) && (tl == 0 || parse_index(ts, tl, &ti)) && (nl == 0 || parse_index(ns, nl, &ni));
    if (!ok)
        return fail(&ps->rep, "malformed face vertex '%s', expected v, v/vt, v//vn or v/vt/vn with integer indices",
                    quote(tok, n).s);
    out->t = out->n = -1;
    if (!resolve_index(ps, vs, vl, vi, m->position_count, "vertex", "vertices", &out->v)) return false;
    if (tl && !resolve_index(ps, ts, tl, ti, m->uv_count, "texture coordinate", "texture coordinates", &out->t))
        return false;
    if (nl && !resolve_index(ps, ns, nl, ni, m->normal_count, "normal", "normals", &out->n)) return false;
    return true;
}

// Whether the triangle (p, q, r) has exactly zero area: its edge cross product, in double, is zero.
static bool zero_area(vec3 p, vec3 q, vec3 r) {
    double ux = (double)q.x - p.x, uy = (double)q.y - p.y, uz = (double)q.z - p.z;
    double vx = (double)r.x - p.x, vy = (double)r.y - p.y, vz = (double)r.z - p.z;
    return uy * vz - uz * vy == 0.0 && uz * vx - ux * vz == 0.0 && ux * vy - uy * vx == 0.0;
}

// f_min and f_max (core/vec.h) for operands that are not NaN, as every coordinate read is: without their NaN
// rule the comparison compiles to one minss or maxss instead of a branch that random data mispredicts.
static inline float min_not_nan(float a, float b) { return a < b ? a : b; }
static inline float max_not_nan(float a, float b) { return a > b ? a : b; }

// bounds3_union(box, tri_bounds(p, q, r)), operand for operand, for points without NaN.
static inline bounds3 box_add_triangle(bounds3 box, vec3 p, vec3 q, vec3 r) {
    vec3 lo = v3(min_not_nan(p.x, min_not_nan(q.x, r.x)), min_not_nan(p.y, min_not_nan(q.y, r.y)),
                 min_not_nan(p.z, min_not_nan(q.z, r.z)));
    vec3 hi = v3(max_not_nan(p.x, max_not_nan(q.x, r.x)), max_not_nan(p.y, max_not_nan(q.y, r.y)),
                 max_not_nan(p.z, max_not_nan(q.z, r.z)));
    return (bounds3){v3(min_not_nan(box.lo.x, lo.x), min_not_nan(box.lo.y, lo.y), min_not_nan(box.lo.z, lo.z)),
                     v3(max_not_nan(box.hi.x, hi.x), max_not_nan(box.hi.y, hi.y), max_not_nan(box.hi.z, hi.z))};
}

// Stores triangle i's corner indices (x, y, z) into normals or uvs in *list. The list starts with the first
// triangle that has one, all -1 before it, so that a mesh without any stores none. False when out of memory.
static bool store_corners(mesh_corners **list, size_t *cap, size_t i, int32_t x, int32_t y, int32_t z) {
    if (!*list && x < 0 && y < 0 && z < 0) return true;
    bool first = !*list;
    if (i >= *cap && !array_reserve((void **)list, cap, i + 1, sizeof **list)) return false;
    for (size_t k = 0; first && k < i; k++) (*list)[k] = (mesh_corners){{-1, -1, -1}};
    (*list)[i] = (mesh_corners){{x, y, z}};
    return true;
}

// Appends triangle (a, b, c) at positions (p, q, r), and grows the mesh's box by it while its corners are at
// hand (the box mesh_compute_bounds would compute, union for union in the same order).
static bool append_triangle(obj_parser *ps, const corner *a, const corner *b, const corner *c, vec3 p, vec3 q, vec3 r) {
    mesh *m = &ps->model->mesh;
    size_t i = m->triangle_count;
    if (i >= MAX_ELEMENTS) return too_many(&ps->rep, "triangles");
    if ((i == ps->tri_cap && !array_reserve((void **)&m->triangles, &ps->tri_cap, i + 1, sizeof *m->triangles)) ||
        !store_corners(&m->normal_corners, &ps->nrm_corner_cap, i, a->n, b->n, c->n) ||
        !store_corners(&m->uv_corners, &ps->uv_corner_cap, i, a->t, b->t, c->t))
        return out_of_memory(&ps->rep);
    m->triangles[i] = (mesh_triangle){{a->v, b->v, c->v}, ps->material};
    m->triangle_count = i + 1;
    m->bounds = box_add_triangle(m->bounds, p, q, r);
    return true;
}

// Appends triangle (a, b, c) unless it has no area (degenerate pieces of a valid polygon are dropped silently).
static bool emit(obj_parser *ps, const corner *a, const corner *b, const corner *c) {
    const vec3 *pos = ps->model->mesh.positions;
    vec3 p = pos[a->v], q = pos[b->v], r = pos[c->v];
    return zero_area(p, q, r) || append_triangle(ps, a, b, c, p, q, r);
}

static void zero_area_face(obj_parser *ps) {
    if (ps->model->zero_area_faces++ == 0) {
        ps->first_zero_line = ps->rep.line;
        warn_at(&ps->rep, ps->rep.line, "face has zero area; skipped");
    }
}

static double cross2(const obj_parser *ps, int a, int b, int c) {
    return (ps->px[b] - ps->px[a]) * (ps->py[c] - ps->py[a]) - (ps->py[b] - ps->py[a]) * (ps->px[c] - ps->px[a]);
}

// Ear clipping of the projected polygon of n corners with orientation sign s (> 0: counter-clockwise).
static bool ear_clip(obj_parser *ps, size_t n, double s) {
    const corner *k = ps->corners;
    for (size_t i = 0; i < n; i++) {
        ps->next[i] = (int)((i + 1) % n);
        ps->prev[i] = (int)((i + n - 1) % n);
    }
    size_t remaining = n;
    int i = 0;
    while (remaining > 3) {
        bool clipped = false;
        for (size_t tries = 0; tries < remaining && !clipped; tries++, i = ps->next[i]) {
            int p = ps->prev[i], q = ps->next[i];
            if (cross2(ps, p, i, q) * s <= 0.0) continue; // reflex or straight: not an ear
            bool empty = true;
            for (int r = ps->next[q]; r != p && empty; r = ps->next[r]) {
                // Corners that coincide with the ear's (the bridge of a keyhole polygon) do not block it.
                bool same = (ps->px[r] == ps->px[p] && ps->py[r] == ps->py[p]) ||
                            (ps->px[r] == ps->px[i] && ps->py[r] == ps->py[i]) ||
                            (ps->px[r] == ps->px[q] && ps->py[r] == ps->py[q]);
                if (!same && cross2(ps, p, i, r) * s >= 0.0 && cross2(ps, i, q, r) * s >= 0.0 &&
                    cross2(ps, q, p, r) * s >= 0.0)
                    empty = false;
            }
            if (!empty) continue;
            if (!emit(ps, &k[p], &k[i], &k[q])) return false;
            ps->next[p] = q;
            ps->prev[q] = p;
            remaining--;
            clipped = true;
            i = p; // the loop's step moves on to q, whose ear status changed
        }
        if (clipped) continue;
        // No ear: drop a straight corner (no area lost) if there is one, else clip anyway and say so.
        int victim = -1;
        for (size_t t = 0, j = (size_t)i; t < remaining && victim < 0; t++, j = (size_t)ps->next[j])
            if (cross2(ps, ps->prev[j], (int)j, ps->next[j]) == 0.0) victim = (int)j;
        if (victim < 0) {
            victim = i;
            if (!ps->warned_bad_polygon) {
                ps->warned_bad_polygon = true;
                warn_at(&ps->rep, ps->rep.line, "face is self-intersecting; its triangulation may be wrong");
            }
            if (!emit(ps, &k[ps->prev[victim]], &k[victim], &k[ps->next[victim]])) return false;
        }
        ps->next[ps->prev[victim]] = ps->next[victim];
        ps->prev[ps->next[victim]] = ps->prev[victim];
        i = ps->next[victim];
        remaining--;
    }
    return emit(ps, &k[ps->prev[i]], &k[i], &k[ps->next[i]]);
}

// Whether every corner of the projected face turns the way of the face (sign s), or the other way by no
// more than moving its three points by the rounding of their coordinates to float could cause. The error of
// (b - a) x (c - a) when each coordinate is off by up to e is at most 2e (|b - a|_1 + |c - a|_1) + 8e^2; it
// is doubled to be safe.
static bool convex_within_rounding(const obj_parser *ps, size_t n, double s) {
    for (size_t i = 0; i < n; i++) {
        int a = (int)((i + n - 1) % n), b = (int)i, c = (int)((i + 1) % n);
        double turn = cross2(ps, a, b, c) * s;
        if (turn >= 0.0) continue;
        double m = fmax(fmax(fmax(fabs(ps->px[a]), fabs(ps->py[a])), fmax(fabs(ps->px[b]), fabs(ps->py[b]))),
                        fmax(fabs(ps->px[c]), fabs(ps->py[c])));
        double e = 0x1p-24 * m;
        double l1 = fabs(ps->px[b] - ps->px[a]) + fabs(ps->py[b] - ps->py[a]) + fabs(ps->px[c] - ps->px[a]) +
                    fabs(ps->py[c] - ps->py[a]);
        if (-turn > 2.0 * (2.0 * e * l1 + 8.0 * e * e)) return false;
    }
    return true;
}

static bool fan(obj_parser *ps, size_t n) {
    for (size_t i = 1; i + 1 < n; i++)
        if (!emit(ps, &ps->corners[0], &ps->corners[i], &ps->corners[i + 1])) return false;
    return true;
}

// A face of three corners: skipped, with a warning, when it has no area.
static bool triangle_face(obj_parser *ps, const corner *k) {
    const vec3 *pos = ps->model->mesh.positions;
    vec3 p = pos[k[0].v], q = pos[k[1].v], r = pos[k[2].v];
    if (zero_area(p, q, r)) {
        zero_area_face(ps);
        return true;
    }
    return append_triangle(ps, &k[0], &k[1], &k[2], p, q, r);
}

// Splits the face's n corners into triangles: fan when convex, ear clipping when concave.
static bool triangulate(obj_parser *ps, size_t n) {
    const mesh *m = &ps->model->mesh;
    const corner *k = ps->corners;
    if (n == 3) return triangle_face(ps, k);
    // Newell's normal: robust for non-planar faces, zero when the face has no area.
    double nx = 0, ny = 0, nz = 0;
    for (size_t i = 0; i < n; i++) {
        vec3 a = m->positions[k[i].v], b = m->positions[k[(i + 1) % n].v];
        nx += ((double)a.y - b.y) * ((double)a.z + b.z);
        ny += ((double)a.z - b.z) * ((double)a.x + b.x);
        nz += ((double)a.x - b.x) * ((double)a.y + b.y);
    }
    double ax = fabs(nx), ay = fabs(ny), az = fabs(nz);
    if (!(ax > 0 || ay > 0 || az > 0) || !isfinite(ax + ay + az)) {
        zero_area_face(ps);
        return true;
    }
    if (n > ps->scratch_cap) {
        // All four scratch arrays share one capacity; each reserve grows its own copy of it.
        size_t c1 = ps->scratch_cap, c2 = c1, c3 = c1, c4 = c1;
        if (!array_reserve((void **)&ps->px, &c1, n, sizeof *ps->px) || !array_reserve((void **)&ps->py, &c2, n, sizeof *ps->py) ||
            !array_reserve((void **)&ps->next, &c3, n, sizeof *ps->next) || !array_reserve((void **)&ps->prev, &c4, n, sizeof *ps->prev))
            return out_of_memory(&ps->rep);
        ps->scratch_cap = c1;
    }
    // Project on the plane of the largest normal component; the cyclic axis order makes the sign of the
    // projected area the sign of that component.
    int axis = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    double s = (axis == 0 ? nx : axis == 1 ? ny : nz) > 0 ? 1.0 : -1.0;
    for (size_t i = 0; i < n; i++) {
        vec3 p = m->positions[k[i].v];
        ps->px[i] = axis == 0 ? p.y : axis == 1 ? p.z : p.x;
        ps->py[i] = axis == 0 ? p.z : axis == 1 ? p.x : p.y;
    }
    bool convex = true;
    for (size_t i = 0; i < n && convex; i++)
        convex = cross2(ps, (int)((i + n - 1) % n), (int)i, (int)((i + 1) % n)) * s >= 0.0;
    if (convex) return fan(ps, n);
    if (n > OBJ_MAX_EAR_CLIP) {
        // Too many corners for ear clipping: a fan, which is right when the face is convex but for the
        // rounding of its corners (a finely divided circle), and worth a warning only when it is not.
        if (!convex_within_rounding(ps, n, s) && !ps->warned_fan) {
            ps->warned_fan = true;
            warn_at(&ps->rep, ps->rep.line, "concave face with %zu vertices triangulated as a fan; it may be wrong", n);
        }
        return fan(ps, n);
    }
    return ear_clip(ps, n, s);
}

static bool obj_face(obj_parser *ps, cursor *c) {
    const char *tok;
    size_t len, n = 0;
    while (next_token(c, &tok, &len)) {
        if (n == OBJ_MAX_FACE_CORNERS)
            return fail(&ps->rep, "face has more than %d vertices, expected at most %d", OBJ_MAX_FACE_CORNERS,
                        OBJ_MAX_FACE_CORNERS);
        if (!array_reserve((void **)&ps->corners, &ps->corner_cap, n + 1, sizeof *ps->corners))
            return out_of_memory(&ps->rep);
        if (!parse_corner(ps, tok, len, &ps->corners[n])) return false;
        n++;
    }
    if (n < 3) return fail(&ps->rep, "face has %zu vertices, expected at least 3", n);
    return triangulate(ps, n);
}

// ---------------------------------------------------------------------------------------------------------
// Fast paths: the plain lines that make up nearly all of a large file (`v`, `vn`, `vt` with numbers, `f`
// with corners v, v/vt, v//vn or v/vt/vn) read in one pass over their bytes, without cutting the line into
// tokens first. Whatever else a line holds (a comment, an unusual number, an index out of range, too many
// numbers, any error) sends it, untouched, to the statements above, which read it again and say what is
// wrong: a fast path only ever accepts what they accept, and stores it through the same functions.

typedef enum fast_result {
    FAST_NO,  // not a line for a fast path: nothing was done, read it as a statement
    FAST_OK,  // read and stored
    FAST_FAIL // stored part of it and failed (out of memory, too many triangles): the message is set
} fast_result;

// Up to `max` numbers to the end of the line; *stop gets the end of the line (its '\n', or `end`).
static inline bool fast_numbers(const char *p, const char *end, float *v, int max, int *count, const char **stop) {
    int k = 0;
    for (;;) {
        while (p < end && is_space(*p)) p++;
        if (p == end || *p == '\n') break;
        if (k == max || !(p = decimal_scan_float(p, end, &v[k]))) return false;
        k++;
        if (p < end && !is_space(*p) && *p != '\n') return false; // "1.5x", "1.#INF", "2#comment"
    }
    *count = k;
    *stop = p;
    return true;
}

// A face index as written (1-based, or negative: relative) into *raw; NULL for anything else: no digits, more
// than 10 digits, or 0.
static inline const char *fast_index_raw(const char *p, const char *end, int64_t *raw) {
    bool neg = p < end && *p == '-';
    p += neg;
    const char *first = p;
    uint64_t v = 0;
    p = decimal_scan_digits(p, end, &v);
    if (p == first || p - first > 10 || v == 0) return NULL;
    *raw = neg ? -(int64_t)v : (int64_t)v;
    return p;
}

// A raw index into `count` elements -> 0-based; false when out of range.
static inline bool fast_index_resolve(int64_t raw, size_t count, int32_t *out) {
    uint64_t v = raw < 0 ? (uint64_t)-raw : (uint64_t)raw;
    if (v > count) return false;
    *out = (int32_t)(raw < 0 ? count - v : v - 1);
    return true;
}

// One face corner as written, v, v/vt, v//vn or v/vt/vn: raw[0], raw[1], raw[2] its indices (0: absent); NULL for
// anything else, including what follows it on the line ("1/2/3/4", "1x", "1#comment").
static inline const char *fast_corner_raw(const char *p, const char *end, int64_t raw[3]) {
    raw[1] = raw[2] = 0;
    if (!(p = fast_index_raw(p, end, &raw[0]))) return NULL;
    if (p < end && *p == '/') {
        p++;
        if ((p == end || *p != '/') && !(p = fast_index_raw(p, end, &raw[1]))) return NULL;
        if (p < end && *p == '/' && !(p = fast_index_raw(p + 1, end, &raw[2]))) return NULL;
    }
    if (p < end && !is_space(*p) && *p != '\n') return NULL;
    return p;
}

// A raw corner resolved against the mesh read so far; false when an index is out of range.
static inline bool fast_corner_resolve(const mesh *m, const int64_t raw[3], corner *k) {
    k->t = k->n = -1;
    return fast_index_resolve(raw[0], m->position_count, &k->v) &&
           (raw[1] == 0 || fast_index_resolve(raw[1], m->uv_count, &k->t)) &&
           (raw[2] == 0 || fast_index_resolve(raw[2], m->normal_count, &k->n));
}

// The corners of a face into ps->corners; *stop gets the end of the line.
static bool fast_corners(obj_parser *ps, const char *p, const char *end, size_t *count, const char **stop) {
    const mesh *m = &ps->model->mesh;
    size_t n = 0;
    for (;;) {
        while (p < end && is_space(*p)) p++;
        if (p == end || *p == '\n') break;
        if (n == OBJ_MAX_FACE_CORNERS ||
            (n == ps->corner_cap && !array_reserve((void **)&ps->corners, &ps->corner_cap, n + 1, sizeof *ps->corners)))
            return false;
        int64_t raw[3];
        if (!(p = fast_corner_raw(p, end, raw)) || !fast_corner_resolve(m, raw, &ps->corners[n++])) return false;
    }
    *count = n;
    *stop = p;
    return n >= 3;
}

// Adds the oldest queued triangle, as the line that read it.
static bool add_oldest_queued(obj_parser *ps) {
    const queued_triangle *t = &ps->queue[ps->queue_head];
    ps->queue_head = (ps->queue_head + 1) % QUEUED_TRIANGLES;
    ps->queue_count--;
    long line = ps->rep.line;
    ps->rep.line = t->line;
    bool ok = triangle_face(ps, t->k);
    ps->rep.line = line;
    return ok;
}

// Adds every queued triangle, in the order of their lines: before any other line is read, so that triangles,
// warnings and errors come in the order of the file.
static bool add_queued(obj_parser *ps) {
    while (ps->queue_count > 0)
        if (!add_oldest_queued(ps)) return false;
    return true;
}

// Queues a triangle read on the current line and starts fetching its corners; the oldest is added when
// the queue is full.
static bool queue_triangle(obj_parser *ps, const corner *k) {
    if (ps->queue_count == QUEUED_TRIANGLES && !add_oldest_queued(ps)) return false;
    queued_triangle *t = &ps->queue[(ps->queue_head + ps->queue_count++) % QUEUED_TRIANGLES];
    memcpy(t->k, k, sizeof t->k);
    t->line = ps->rep.line;
    const vec3 *pos = ps->model->mesh.positions;
    for (int i = 0; i < 3; i++) prefetch_read(&pos[k[i].v]);
    return true;
}

/// The lines the fast paths read.
typedef enum fast_kind { FAST_VERTEX, FAST_NORMAL, FAST_TEXCOORD, FAST_FACE, FAST_OTHER } fast_kind;

static inline fast_kind fast_kind_of(const char *s, const char *end) {
    if (end - s < 3) return FAST_OTHER;
    if (s[0] == 'v' && is_space(s[1])) return FAST_VERTEX;
    if (s[0] == 'f' && is_space(s[1])) return FAST_FACE;
    if (s[0] == 'v' && s[1] == 'n' && is_space(s[2])) return FAST_NORMAL;
    if (s[0] == 'v' && s[1] == 't' && is_space(s[2])) return FAST_TEXCOORD;
    return FAST_OTHER;
}

// The numbers of a v, vn or vt line at s (as many as its kind takes); *stop gets the end of the line.
static inline bool fast_line_numbers(fast_kind kind, const char *s, const char *end, float *v, int *count,
                                     const char **stop) {
    if (kind == FAST_VERTEX) return fast_numbers(s + 2, end, v, 7, count, stop) && *count >= 3;
    if (kind == FAST_NORMAL) return fast_numbers(s + 3, end, v, 3, count, stop) && *count == 3;
    return fast_numbers(s + 3, end, v, 3, count, stop) && *count >= 1;
}

// Stores what a fast path read: a v, vn or vt line's numbers, or a face of `corners` corners in ps->corners.
static fast_result fast_store(obj_parser *ps, fast_kind kind, const float *v, int count, size_t corners) {
    if (kind == FAST_FACE && corners == 3) return queue_triangle(ps, ps->corners) ? FAST_OK : FAST_FAIL;
    if (!add_queued(ps)) return FAST_FAIL;
    bool ok = kind == FAST_FACE     ? triangulate(ps, corners)
              : kind == FAST_VERTEX ? add_position(ps, v)
              : kind == FAST_NORMAL ? add_normal(ps, v)
                                    : add_texcoord(ps, v, count);
    return ok ? FAST_OK : FAST_FAIL;
}

// The line at s by a fast path, if it is one of theirs; *next gets the start of the next line.
static fast_result fast_line(obj_parser *ps, const char *s, const char *end, const char **next) {
    fast_kind kind = fast_kind_of(s, end);
    if (kind == FAST_OTHER) return FAST_NO;
    const char *stop;
    float v[7];
    int count = 0;
    size_t corners = 0;
    bool ok = kind == FAST_FACE ? fast_corners(ps, s + 2, end, &corners, &stop)
                                : fast_line_numbers(kind, s, end, v, &count, &stop);
    // A line longer than the limit is an error however well formed: the statement reader says so.
    if (!ok || (size_t)(stop - s) > OBJ_MAX_LINE_BYTES) return FAST_NO;
    *next = stop < end ? stop + 1 : end;
    return fast_store(ps, kind, v, count, corners);
}

static bool obj_usemtl(obj_parser *ps, cursor *c) {
    const char *name;
    size_t n;
    rest_of_line(c, &name, &n);
    if (n == 0) return fail(&ps->rep, "'usemtl' needs a material name");
    size_t found;
    int32_t slot = strmap_get(&ps->slots, name, n, &found) ? (int32_t)found : -1;
    if (slot < 0) {
        obj_model *mo = ps->model;
        if (mo->material_count >= MAX_ELEMENTS) return too_many(&ps->rep, "materials");
        if (!array_reserve((void **)&mo->materials, &ps->slot_cap, mo->material_count + 1, sizeof *mo->materials))
            return out_of_memory(&ps->rep);
        obj_material *m = &mo->materials[mo->material_count];
        memset(m, 0, sizeof *m);
        m->name = dup_n(name, n);
        if (!m->name) return out_of_memory(&ps->rep);
        m->mat = material_default(MAT_LAMBERTIAN);
        m->line = ps->rep.line;
        slot = (int32_t)mo->material_count++;
        if (!strmap_put(&ps->slots, m->name, n, (size_t)slot)) return out_of_memory(&ps->rep);
    }
    ps->material = slot;
    return true;
}

// Reads one material library (once) and appends its definitions; a missing file is a warning.
static bool obj_library(obj_parser *ps, const char *path, const char *shown, size_t shown_len) {
    for (size_t i = 0; i < ps->lib_count; i++)
        if (strcmp(ps->libs[i], path) == 0) return true;
    size_t len;
    int e;
    char *text = read_file(path, MTL_MAX_FILE_BYTES, &len, &e);
    if (!text) {
        quoted q = quote_path(shown, shown_len);
        if (e == ENOMEM) {
            ps->rep.nomem = true;
            return fail(&ps->rep, "out of memory reading material library '%s'", q.s);
        }
        if (e == EFBIG)
            return fail(&ps->rep, "material library '%s' is larger than %zu bytes (%zu MiB)", q.s,
                        (size_t)MTL_MAX_FILE_BYTES, (size_t)MTL_MAX_FILE_BYTES >> 20);
        warn_at(&ps->rep, ps->rep.line, "cannot open material library '%s' (%s); its materials are undefined", q.s,
                filepath_problem_text(e));
        return true;
    }
    char *copy = dup_n(path, strlen(path));
    if (!copy || !array_reserve((void **)&ps->libs, &ps->lib_cap, ps->lib_count + 1, sizeof *ps->libs)) {
        free(copy);
        free(text);
        return out_of_memory(&ps->rep);
    }
    ps->libs[ps->lib_count++] = copy;
    obj_material *defs;
    size_t count;
    glint_status status = mtl_parse_counted(path, text, len, ps->opt, &defs, &count, &ps->model->warning_count, ps->rep.err);
    free(text);
    if (status != GLINT_OK) {
        ps->rep.nomem = status == GLINT_ERR_RENDER;
        return false;
    }
    bool ok = true;
    for (size_t i = 0; i < count; i++) {
        obj_material *d = &defs[i];
        size_t nl = strlen(d->name);
        // A name that an earlier library defined keeps that first definition.
        bool keep = ok && !strmap_get(&ps->def_names, d->name, nl, NULL);
        if (keep && (ps->def_count >= MAX_ELEMENTS ||
                     !array_reserve((void **)&ps->defs, &ps->def_cap, ps->def_count + 1, sizeof *ps->defs) ||
                     !strmap_put(&ps->def_names, d->name, nl, ps->def_count)))
            keep = ok = out_of_memory(&ps->rep);
        if (keep) {
            ps->defs[ps->def_count++] = *d; // the strings now belong to ps->defs
            continue;
        }
        free(d->name);
        free(d->diffuse_map);
    }
    free(defs);
    return ok;
}

static bool obj_mtllib(obj_parser *ps, cursor *c) {
    const char *names;
    size_t n;
    rest_of_line(c, &names, &n);
    if (n == 0) return fail(&ps->rep, "'mtllib' needs a file name");
    if (ps->opt && ps->opt->skip_files) return true;
    char *whole = join_path(ps->dir, ps->dir_len, names, n);
    if (!whole) return out_of_memory(&ps->rep);
    // The whole argument may be one name with blanks; otherwise it is a list of names.
    struct stat st;
    bool single = filepath_problem(whole, &st) == 0 || (!memchr(names, ' ', n) && !memchr(names, '\t', n));
    if (single) {
        bool ok = obj_library(ps, whole, names, n);
        free(whole);
        return ok;
    }
    free(whole);
    cursor list = {names, names + n};
    const char *tok;
    size_t len;
    while (next_token(&list, &tok, &len)) {
        char *path = join_path(ps->dir, ps->dir_len, tok, len);
        if (!path) return out_of_memory(&ps->rep);
        bool ok = obj_library(ps, path, tok, len);
        free(path);
        if (!ok) return false;
    }
    return true;
}

static bool obj_statement(obj_parser *ps, cursor *c) {
    const char *kw;
    size_t n;
    if (!next_token(c, &kw, &n)) return true;
    if (n == 1) {
        switch (kw[0]) {
        case 'v': return obj_vertex(ps, c);
        case 'f': return obj_face(ps, c);
        case 'o': case 'g': case 's': return true; // objects, groups and smoothing groups carry nothing we need
        default: break;
        }
    } else if (n == 2 && kw[0] == 'v') {
        if (kw[1] == 'n') return obj_normal(ps, c);
        if (kw[1] == 't') return obj_texcoord(ps, c);
    } else if (token_is(kw, n, "usemtl")) {
        return obj_usemtl(ps, c);
    } else if (token_is(kw, n, "mtllib")) {
        return obj_mtllib(ps, c);
    }
    warn_unsupported(&ps->rep, kw, n);
    return true;
}

static bool obj_line(void *state, cursor *c) { return obj_statement(state, c); }

// Every line of (a part of) an OBJ text, counting on from ps->rep.line: by a fast path when it takes the
// line, else as a statement.
static bool obj_lines(obj_parser *ps, const char *text, size_t length) {
    const char *s = text, *end = text + length;
    bool fast = !(ps->opt && ps->opt->statements_only);
    while (s < end) {
        ps->rep.line++;
        fast_result r = fast ? fast_line(ps, s, end, &s) : FAST_NO;
        if (r == FAST_FAIL || (r == FAST_NO && (!add_queued(ps) || !read_line(s, end, &ps->rep, obj_line, ps, &s))))
            return false;
    }
    return add_queued(ps);
}

void obj_model_free(obj_model *m) {
    mesh_free(&m->mesh);
    obj_materials_free(m->materials, m->material_count);
    for (size_t i = 0; i < m->library_count; i++) free(m->libraries[i]);
    free(m->libraries);
    memset(m, 0, sizeof *m);
    m->mesh.bounds = bounds3_empty();
}

// Gives each usemtl slot its definition from the libraries, or warns and keeps the fallback.
static bool resolve_materials(obj_parser *ps) {
    obj_model *mo = ps->model;
    for (size_t i = 0; i < mo->material_count; i++) {
        obj_material *slot = &mo->materials[i];
        size_t d;
        if (!strmap_get(&ps->def_names, slot->name, strlen(slot->name), &d)) {
            warn_at(&ps->rep, slot->line, "material '%s' is not defined in any material library; using the default material",
                    quote(slot->name, strlen(slot->name)).s);
            continue;
        }
        const obj_material *def = &ps->defs[d];
        slot->defined = true;
        slot->mat = def->mat;
        if (def->diffuse_map && !(slot->diffuse_map = dup_n(def->diffuse_map, strlen(def->diffuse_map))))
            return out_of_memory(&ps->rep);
    }
    return true;
}

// Readies the parser for the first line of file `name`.
static void obj_begin(obj_parser *ps, const char *name, const obj_options *opt, obj_model *out, glint_error *err) {
    memset(out, 0, sizeof *out);
    out->mesh.bounds = bounds3_empty();
    memset(ps, 0, sizeof *ps);
    ps->rep.name = name;
    ps->rep.opt = opt;
    ps->rep.err = err;
    ps->rep.warnings = &out->warning_count;
    ps->model = out;
    ps->opt = opt;
    ps->material = -1;
    ps->dir = name;
    ps->dir_len = filepath_dir_length(name);
}

// After the last line (ok) or a failure (!ok): gives the materials their definitions, says what is left to
// say, frees the parser's scratch, and on failure the model too.
static glint_status obj_end(obj_parser *ps, bool ok) {
    obj_model *out = ps->model;
    if (ok) ok = resolve_materials(ps);
    if (ok) {
        if (out->zero_area_faces > 1)
            warn_at(&ps->rep, 0, "%zu zero-area faces skipped in total (the first on line %ld)", out->zero_area_faces,
                    ps->first_zero_line);
        if (out->mesh.triangle_count == 0) warn_at(&ps->rep, 0, "no faces; the mesh is empty");
    }
    free(ps->corners);
    free(ps->px);
    free(ps->py);
    free(ps->next);
    free(ps->prev);
    strmap_free(&ps->slots);
    strmap_free(&ps->def_names);
    obj_materials_free(ps->defs, ps->def_count);
    // The model keeps the list of libraries read: they are inputs of the scene as much as the OBJ file.
    out->libraries = ps->libs;
    out->library_count = ps->lib_count;
    if (!ok) {
        obj_model_free(out);
        return ps->rep.nomem ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

glint_status obj_parse(const char *name, const char *text, size_t length, const obj_options *opt, obj_model *out,
                       glint_error *err) {
    obj_parser ps;
    obj_begin(&ps, name, opt, out, err);
    return obj_end(&ps, obj_lines(&ps, text, length));
}

// Reads the open OBJ file f block by block and parses the complete lines of each block as it arrives, exactly
// as obj_parse parses them: a large file is never held whole, which spares copying it into fresh memory (a
// page fault every 4 KiB) and reading it back from far away. False on a parse failure (message set, *errnum
// 0) or a read failure (*errnum: the read's errno, EFBIG past OBJ_MAX_FILE_BYTES, ENOMEM).
// The buffer of a line that fills it, doubled up to one byte more than a line may hold. False when it already
// holds that (the line is too long: *errnum stays 0) or memory runs out (*errnum ENOMEM).
static bool grow_line_buffer(char **buf, size_t *cap, int *errnum) {
    if (*cap > OBJ_MAX_LINE_BYTES) return false;
    size_t bigger = *cap > OBJ_MAX_LINE_BYTES / 2 ? OBJ_MAX_LINE_BYTES + 1 : *cap * 2;
    char *grown = realloc(*buf, bigger);
    if (!grown) {
        *errnum = ENOMEM;
        return false;
    }
    *buf = grown;
    *cap = bigger;
    return true;
}

// A line longer than the limit, `length` bytes of it read: an error that gives its length, so read on to its end
// (through buf). Always false.
static bool line_too_long_read_on(obj_parser *ps, FILE *f, char *buf, size_t cap, size_t length) {
    char *nl = NULL;
    for (size_t got = 1; !nl && got > 0 && length <= OBJ_MAX_FILE_BYTES;) {
        got = fread(buf, 1, cap, f);
        nl = memchr(buf, '\n', got);
        length += nl ? (size_t)(nl - buf) : got;
    }
    ps->rep.line++;
    return line_too_long(&ps->rep, length);
}

static bool obj_read_stream(obj_parser *ps, FILE *f, int *errnum) {
    *errnum = 0;
    size_t cap = OBJ_READ_BLOCK, have = 0, total = 0; // have: bytes of buf not parsed yet, a part of a line
    char *buf = malloc(cap);
    bool ok = buf != NULL, eof = false;
    if (!ok) *errnum = ENOMEM;
    while (ok && !eof) {
        if (have == cap && !grow_line_buffer(&buf, &cap, errnum)) { // the buffer is one unfinished line
            ok = !*errnum; // too long: said below
            break;
        }
        size_t got = fread(buf + have, 1, cap - have, f);
        eof = got < cap - have;
        if (eof && ferror(f)) *errnum = errno ? errno : EIO;
        else if ((total += got) > OBJ_MAX_FILE_BYTES) *errnum = EFBIG;
        if (*errnum) {
            ok = false;
            break;
        }
        have += got;
        // Parse up to the last line end; at the end of the file, the last line too.
        size_t upto = have;
        while (!eof && upto > 0 && buf[upto - 1] != '\n') upto--;
        ok = obj_lines(ps, buf, upto);
        memmove(buf, buf + upto, have - upto);
        have -= upto;
    }
    if (ok && !eof) ok = line_too_long_read_on(ps, f, buf, cap, have);
    free(buf);
    return ok;
}

// ---------------------------------------------------------------------------------------------------------
// On several threads: a large file is read in blocks; while one thread stores the lines of a block (the steps
// above, in the file's order: the same mesh, warnings and errors as reading it alone), the others read the
// numbers and face corners of the next block's lines into records. Lines the records cannot hold (anything
// but a plain v, vn, vt or f line of at most PRE_CORNERS corners) are kept as runs, read when they are stored
// by obj_lines itself; so a record is at least 8 bytes of the file (a fast line) or a run, and the records of a
// block take at most 16 times its size.

/// Bytes of a block; corners a face record holds.
enum { OBJ_PARALLEL_BLOCK = 1 << 20, PRE_CORNERS = 4 };
/// Files from this size up are read on several threads.
#define OBJ_PARALLEL_MIN ((size_t)4 << 20)

/// Threads that read one file, at most (the render's limit).
enum { OBJ_MAX_THREADS = 256 };

/// One line as the fast paths read it, before anything is stored; or a run of lines they do not take.
typedef struct pre_line {
    const char *start; ///< the line, or the run's first line
    uint32_t length;   ///< FAST_OTHER: the run's bytes, whole lines
    uint8_t kind;      ///< fast_kind; FAST_OTHER: a run, read when it is stored
    uint8_t count;     ///< numbers, or corners
    union {
        float v[7];
        int32_t raw[PRE_CORNERS][3]; ///< fast_corner_raw's indices (a line with one beyond int32 is in a run)
    } u;
} pre_line;
_Static_assert(sizeof(pre_line) <= 64, "records of a block stay within 16 times its bytes");
_Static_assert(OBJ_MAX_LINE_BYTES < UINT32_MAX / 2, "a run's length holds any line");

/// The records of one part of a block, in line order.
typedef struct pre_part {
    pre_line *lines;
    size_t count, cap;
    bool nomem;
} pre_part;

/// A block of complete lines, text[0, upto), and the start of the next line after it, text[upto, have).
typedef struct obj_block {
    char *text;
    size_t cap, have, upto;
    bool eof;
    pre_part *parts; ///< the block's parts (obj_read_parallel's `parts` of them), split at line ends
} obj_block;

// Whether a corner's raw indices fit a record (an index beyond int32 is out of range for any mesh).
static inline bool fits_int32(const int64_t raw[3]) {
    return raw[0] >= INT32_MIN && raw[0] <= INT32_MAX && raw[1] >= INT32_MIN && raw[1] <= INT32_MAX &&
           raw[2] >= INT32_MIN && raw[2] <= INT32_MAX;
}

// What the fast paths would read of the line at s, into *pl (kind FAST_OTHER: none of it), storing nothing;
// returns the next line's start.
static const char *pre_scan_line(const char *s, const char *end, pre_line *pl) {
    pl->start = s;
    pl->kind = FAST_OTHER;
    fast_kind kind = fast_kind_of(s, end);
    const char *stop = NULL;
    bool ok = false;
    if (kind == FAST_FACE) {
        const char *p = s + 2;
        size_t n = 0;
        for (ok = true;;) {
            while (p < end && is_space(*p)) p++;
            if (p == end || *p == '\n') break;
            int64_t raw[3];
            if (n == PRE_CORNERS || !(p = fast_corner_raw(p, end, raw)) || !fits_int32(raw)) {
                ok = false;
                break;
            }
            for (int k = 0; k < 3; k++) pl->u.raw[n][k] = (int32_t)raw[k];
            n++;
        }
        stop = p;
        ok = ok && n >= 3;
        pl->count = (uint8_t)n;
    } else if (kind != FAST_OTHER) {
        int count = 0;
        ok = fast_line_numbers(kind, s, end, pl->u.v, &count, &stop);
        pl->count = (uint8_t)count;
    }
    if (ok && (size_t)(stop - s) <= OBJ_MAX_LINE_BYTES) {
        pl->kind = (uint8_t)kind;
        return stop < end ? stop + 1 : end;
    }
    const char *nl = memchr(s, '\n', (size_t)(end - s));
    return nl ? nl + 1 : end;
}

// The line (or run) of record pl stored as obj_lines stores it. False on a failure (message set).
static bool pre_store(obj_parser *ps, const pre_line *pl, const char *end) {
    if (pl->kind == FAST_OTHER) return obj_lines(ps, pl->start, pl->length);
    ps->rep.line++;
    if (pl->kind == FAST_FACE) {
        if (ps->corner_cap < PRE_CORNERS &&
            !array_reserve((void **)&ps->corners, &ps->corner_cap, PRE_CORNERS, sizeof *ps->corners))
            return out_of_memory(&ps->rep);
        bool ok = true;
        for (size_t k = 0; ok && k < pl->count; k++) {
            const int32_t *r = pl->u.raw[k];
            ok = fast_corner_resolve(&ps->model->mesh, (const int64_t[3]){r[0], r[1], r[2]}, &ps->corners[k]);
        }
        if (ok) return fast_store(ps, FAST_FACE, NULL, 0, pl->count) == FAST_OK;
    } else {
        return fast_store(ps, (fast_kind)pl->kind, pl->u.v, pl->count, 0) == FAST_OK;
    }
    // A corner out of range: the line as obj_lines reads it (which gives the message).
    const char *next;
    fast_result r = fast_line(ps, pl->start, end, &next);
    return r == FAST_OK ||
           (r == FAST_NO && add_queued(ps) && read_line(pl->start, end, &ps->rep, obj_line, ps, &next));
}

/// One round of the parallel reader: store block `store` (NULL: none) while the parts of block `scan` (NULL:
/// none) are read. Item 0 stores, item k > 0 reads part k - 1.
typedef struct pre_round {
    obj_parser *ps;
    const obj_block *store;
    obj_block *scan;
    size_t parts;
    bool ok;
} pre_round;

// The first line of text[0, n) that starts at or after `at` (text + n when none does).
static const char *line_start_from(const char *text, size_t n, size_t at) {
    if (at == 0 || at >= n) return text + (at < n ? at : n);
    const char *nl = memchr(text + at - 1, '\n', n - (at - 1));
    return nl ? nl + 1 : text + n;
}

static void pre_round_run(void *ctx, size_t item) {
    pre_round *rd = ctx;
    if (item == 0) {
        const obj_block *b = rd->store;
        const char *end = b ? b->text + b->upto : NULL;
        for (size_t k = 0; b && rd->ok && k < rd->parts; k++)
            for (size_t i = 0; rd->ok && i < b->parts[k].count; i++) rd->ok = pre_store(rd->ps, &b->parts[k].lines[i], end);
        if (b && rd->ok) rd->ok = add_queued(rd->ps); // as obj_lines ends a block
        return;
    }
    obj_block *b = rd->scan;
    if (!b) return;
    size_t k = item - 1, n = b->upto;
    // Part k: from the first line that starts at or after k n / parts to the first at or after (k + 1) n / parts.
    const char *text = b->text, *end = text + n;
    size_t at = (size_t)((uint64_t)n * k / rd->parts), to = (size_t)((uint64_t)n * (k + 1) / rd->parts);
    const char *s = line_start_from(text, n, at), *e = line_start_from(text, n, to);
    pre_part *part = &b->parts[k];
    part->count = 0;
    while (s < e) {
        if (part->count == part->cap &&
            !array_reserve((void **)&part->lines, &part->cap, part->count + 1, sizeof *part->lines)) {
            part->nomem = true;
            return;
        }
        pre_line *pl = &part->lines[part->count];
        const char *next = pre_scan_line(s, end, pl);
        size_t bytes = (size_t)(next - s);
        pre_line *last = part->count ? pl - 1 : NULL;
        if (pl->kind != FAST_OTHER) {
            part->count++;
        } else if (last && last->kind == FAST_OTHER && last->length <= UINT32_MAX - bytes) {
            last->length += (uint32_t)bytes; // the line joins the run before it
        } else {
            pl->length = (uint32_t)bytes; // a line is shorter than a block's buffer (OBJ_MAX_LINE_BYTES + 1)
            part->count++;
        }
        s = next;
    }
}

// Fills block b: the unfinished line that `prev` ended with, then up to `block` bytes more of the file, cut at the
// last line end (all of it at the end of the file); more only while the unfinished line alone fills it. False on a
// read failure (*errnum set) or a line longer than the limit (*errnum 0, b->eof false, b->have its bytes so far).
static bool fill_block(FILE *f, obj_block *b, const obj_block *prev, size_t block, size_t *total, int *errnum) {
    size_t carried = prev ? prev->have - prev->upto : 0; // at most OBJ_MAX_LINE_BYTES: prev had a line end
    if (carried + block > b->cap && b->cap <= OBJ_MAX_LINE_BYTES) {
        // Room for the unfinished line and a block after it, within the most a line's buffer may take.
        size_t want = carried + block < OBJ_MAX_LINE_BYTES + 1 ? carried + block : OBJ_MAX_LINE_BYTES + 1;
        char *grown = realloc(b->text, want);
        if (!grown) {
            *errnum = ENOMEM;
            return false;
        }
        b->text = grown;
        b->cap = want;
    }
    b->have = carried;
    if (carried) memmove(b->text, prev->text + prev->upto, carried);
    b->upto = 0;
    for (;;) {
        if (b->have == b->cap && !grow_line_buffer(&b->text, &b->cap, errnum)) return false; // one unfinished line
        size_t room = b->cap - b->have, want = room < block ? room : block;
        size_t got = fread(b->text + b->have, 1, want, f);
        b->eof = got < want;
        if (b->eof && ferror(f)) *errnum = errno ? errno : EIO;
        else if ((*total += got) > OBJ_MAX_FILE_BYTES) *errnum = EFBIG;
        if (*errnum) return false;
        size_t before = b->have; // the bytes before hold no line end (the unfinished line)
        b->have += got;
        size_t upto = b->have;
        while (!b->eof && upto > before && b->text[upto - 1] != '\n') upto--;
        if (upto > before || b->eof) {
            b->upto = upto;
            return true;
        }
    }
}

// obj_read_stream on the pool's threads (see above): the same mesh, warnings and errors.
static bool obj_read_parallel(obj_parser *ps, FILE *f, thread_pool *pool, size_t block, int *errnum) {
    *errnum = 0;
    size_t parts = 2 * (size_t)thread_pool_size(pool), total = 0;
    obj_block blocks[2] = {{0}, {0}};
    bool ok = true;
    for (int i = 0; ok && i < 2; i++) {
        blocks[i].text = malloc(block);
        blocks[i].cap = block;
        blocks[i].parts = calloc(parts, sizeof *blocks[i].parts);
        ok = blocks[i].text && blocks[i].parts;
    }
    obj_block *cur = &blocks[0], *spare = &blocks[1], *pending = NULL; // pending: read, not stored yet
    bool filled = false;
    if (!ok) *errnum = ENOMEM;
    else filled = fill_block(f, cur, NULL, block, &total, errnum);
    while (filled) {
        pre_round rd = {ps, pending, cur, parts, true};
        thread_pool_run(pool, parts + 1, pre_round_run, &rd);
        pending = NULL;
        if (!rd.ok) { // a line failed: its message is set
            ok = false;
            break;
        }
        bool nomem = false;
        for (size_t k = 0; k < parts; k++) nomem = nomem || cur->parts[k].nomem;
        if (nomem) {
            ok = out_of_memory(&ps->rep);
            break;
        }
        pending = cur;
        if (cur->eof) break;
        filled = fill_block(f, spare, cur, block, &total, errnum);
        obj_block *t = cur;
        cur = spare;
        spare = t;
    }
    if (ok && pending) {
        pre_round rd = {ps, pending, NULL, parts, true};
        pre_round_run(&rd, 0);
        ok = rd.ok;
        if (!ok) *errnum = 0; // a line before the read failure failed first
    }
    if (ok && !filled && !*errnum) ok = line_too_long_read_on(ps, f, cur->text, cur->cap, cur->have);
    if (*errnum) ok = false;
    for (int i = 0; i < 2; i++) {
        for (size_t k = 0; blocks[i].parts && k < parts; k++) free(blocks[i].parts[k].lines);
        free(blocks[i].parts);
        free(blocks[i].text);
    }
    return ok;
}

// The message of a file that cannot be read.
static glint_status obj_file_failure(const char *path, int e, glint_error *err) {
    glint_status st = e == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    if (!err) return st;
    if (e == ENOMEM) snprintf(err->message, sizeof err->message, "%s: out of memory reading the file", path);
    else if (e == EFBIG)
        snprintf(err->message, sizeof err->message, "%s: the OBJ file is larger than %zu bytes (%zu GiB)", path,
                 (size_t)OBJ_MAX_FILE_BYTES, (size_t)OBJ_MAX_FILE_BYTES >> 30);
    else snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, filepath_problem_text(e));
    return st;
}

glint_status obj_load(const char *path, const obj_options *opt, obj_model *out, glint_error *err) {
    memset(out, 0, sizeof *out);
    out->mesh.bounds = bounds3_empty();
    size_t size;
    int e;
    FILE *f = open_file(path, OBJ_MAX_FILE_BYTES, &size, &e);
    if (!f) return obj_file_failure(path, e, err);
    obj_parser ps;
    obj_begin(&ps, path, opt, out, err);
    // A large file on several threads (fast paths only: statements_only reads every line as a statement).
    int threads = opt && opt->threads ? opt->threads : 1;
    if (threads < 0) threads = thread_pool_online_cpus();
    if (threads > OBJ_MAX_THREADS) threads = OBJ_MAX_THREADS;
    size_t min = opt && opt->parallel_min ? opt->parallel_min : OBJ_PARALLEL_MIN;
    size_t block = opt && opt->parallel_min ? (opt->parallel_min > 16 ? opt->parallel_min : 16) : OBJ_PARALLEL_BLOCK;
    thread_pool *pool = threads > 1 && size >= min && !opt->statements_only ? thread_pool_start(threads) : NULL;
    bool ok = pool && thread_pool_size(pool) > 1 ? obj_read_parallel(&ps, f, pool, block, &e)
                                                 : obj_read_stream(&ps, f, &e);
    thread_pool_stop(pool);
    fclose(f);
    glint_status st = obj_end(&ps, ok);
    return ok || !e ? st : obj_file_failure(path, e, err);
}
