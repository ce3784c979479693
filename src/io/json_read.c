// json_read.c — typed JSON reading: values walked in step with json_scan's token index, so that every
// rejected value is reported with its file:line:col and quoted as the file spells it.
#include "io/json_read.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---------------------------------------------------------------------------------------------
// Positions and messages

size_t jr_offset(const json_reader *rd, uint32_t tok) { return rd->ix->tok[tok].offset; }

void jr_vformat(const json_reader *rd, char *buf, size_t size, size_t offset, const char *label, const char *fmt,
                va_list ap) {
    char prefix[400];
    if (rd->call) {
        snprintf(prefix, sizeof prefix, "%s: %s", rd->name, label);
    } else {
        size_t line, col;
        json_line_col(rd->text, rd->len, offset, &line, &col);
        snprintf(prefix, sizeof prefix, "%s:%zu:%zu: %s", rd->name, line, col, label);
    }
    status_vformat(buf, size, prefix, fmt, ap);
}

bool jr_fail_at(json_reader *rd, size_t offset, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    jr_vformat(rd, rd->err->message, sizeof rd->err->message, offset, "", fmt, ap);
    va_end(ap);
    rd->status = GLINT_ERR_INPUT;
    return false;
}

bool jr_fail_internal(json_reader *rd, uint32_t tok) {
    size_t off = tok < rd->ix->count ? jr_offset(rd, tok) : rd->len;
    return jr_fail_at(rd, off, "internal error: the JSON scanner and cJSON disagree about this value");
}

static bool is_word_char(char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '+' || c == '-' ||
           c == '.' || c == '_';
}

// Copies source text [from, to) into buf, cut at `limit` bytes on a UTF-8 boundary with `ellipsis` added.
static void copy_source(const json_reader *rd, size_t from, size_t to, size_t limit, const char *ellipsis, char *buf,
                        size_t size) {
    size_t n = to - from;
    bool cut = n > limit;
    if (cut) {
        n = limit;
        while (n > 0 && ((unsigned char)rd->text[from + n] & 0xC0u) == 0x80u) n--;
    }
    snprintf(buf, size, "%.*s%s", (int)n, rd->text + from, cut ? ellipsis : "");
}

/// The end of the string whose opening quote is at p: the offset of its closing quote (or of the end).
static size_t string_end(const json_reader *rd, size_t p) {
    size_t q = p + 1, len = rd->len;
    while (q < len && rd->text[q] != '"') q += rd->text[q] == '\\' ? 2 : 1;
    return q > len ? len : q;
}

/// The string whose opening quote is at p as the file spells it, quotes included, cut after 40 bytes.
static const char *describe_string(const json_reader *rd, size_t p, char *buf, size_t size) {
    size_t q = string_end(rd, p), len = rd->len;
    if (q - p > 40) copy_source(rd, p, q, 40, "...\"", buf, size);
    else copy_source(rd, p, q < len ? q + 1 : len, 41, "", buf, size);
    return buf;
}

const char *jr_describe_path(const json_reader *rd, jr_val v, char *buf, size_t size) {
    if (!cJSON_IsString(v.item)) return jr_describe(rd, v, buf, size);
    size_t p = jr_offset(rd, v.tok), q = string_end(rd, p);
    if (q - (p + 1) <= JR_PATH_SHOWN) {
        // Whole, quotes included (describe_string would cut it after 40 bytes, losing the file name).
        copy_source(rd, p, q < rd->len ? q + 1 : rd->len, JR_PATH_SHOWN + 2, "", buf, size);
        return buf;
    }
    // Keep the end, where the file name is: start after an escape's backslash or inside a UTF-8 sequence
    // never, so the excerpt stays valid text.
    size_t from = q - JR_PATH_SHOWN;
    while (from < q && (((unsigned char)rd->text[from] & 0xC0u) == 0x80u || rd->text[from - 1] == '\\')) from++;
    snprintf(buf, size, "\"...%.*s\"", (int)(q - from), rd->text + from);
    return buf;
}

void jr_number_text(double x, char *buf, size_t size) {
    if (!isfinite(x)) { // JSON has no infinity: the number a file would write for one, which reads back as it
        snprintf(buf, size, isnan(x) ? "\"NaN\"" : x > 0 ? "1e999" : "-1e999");
        return;
    }
    int digits = 1;
    while (digits < 17) {
        snprintf(buf, size, "%.*g", digits, x);
        if (strtod(buf, NULL) == x) break;
        digits++;
    }
    // Plain digits where a person writes them (180, -10, 123456), an exponent for the very large: 1e39.
    int e = x != 0.0 ? (int)floor(log10(fabs(x))) : 0;
    if (e >= digits && e < 17) digits = e + 1;
    snprintf(buf, size, "%.*g", digits, x);
    char *at = strchr(buf, 'e'); // 1e+39 -> 1e39, 1e-07 -> 1e-7
    if (!at) return;
    char *d = at + 1 + (at[1] == '+' || at[1] == '-');
    size_t zeros = 0;
    while (d[zeros] == '0' && d[zeros + 1]) zeros++;
    memmove(at[1] == '+' ? at + 1 : d, d + zeros, strlen(d + zeros) + 1);
}

// Appends v to buf (at *n) as a person writes JSON: "[1, 0.5, [2, 3]]", numbers at their shortest; false for an
// object inside, or when it no longer fits.
static bool describe_canonical(const cJSON *v, char *buf, size_t size, size_t *n) {
    char part[64];
    if (cJSON_IsArray(v)) {
        if (*n + 1 >= size) return false;
        buf[(*n)++] = '[';
        for (const cJSON *e = v->child; e; e = e->next) {
            if (e != v->child) {
                if (*n + 2 >= size) return false;
                buf[(*n)++] = ',', buf[(*n)++] = ' ';
            }
            if (!describe_canonical(e, buf, size, n)) return false;
        }
        if (*n + 1 >= size) return false;
        buf[(*n)++] = ']';
        buf[*n] = '\0';
        return true;
    }
    if (cJSON_IsNumber(v)) jr_number_text(v->valuedouble, part, sizeof part);
    else if (cJSON_IsString(v) || cJSON_IsObject(v) || cJSON_IsRaw(v)) return false;
    else snprintf(part, sizeof part, "%s", cJSON_IsTrue(v) ? "true" : cJSON_IsFalse(v) ? "false" : "null");
    int w = snprintf(buf + *n, size - *n, "%s", part);
    if (w < 0 || (size_t)w >= size - *n) return false;
    *n += (size_t)w;
    return true;
}

/// The value as the file spells it, for "got ..." clauses: "abc", 1e999, [1, 2], or "an object".
const char *jr_describe(const json_reader *rd, jr_val v, char *buf, size_t size) {
    size_t p = jr_offset(rd, v.tok), len = rd->len;
    const cJSON *it = v.item;
    if (cJSON_IsObject(it)) return "an object";
    if (cJSON_IsArray(it) && rd->call) {
        // A call's value was printed without spaces: quote a short array as a file usually spells one.
        size_t n = 0;
        if (describe_canonical(it, buf, size, &n) && n <= 40) return buf;
    }
    if (cJSON_IsArray(it)) {
        // Short one-line arrays are quoted as written; others are summarised.
        int depth = 0;
        bool in_string = false;
        for (size_t q = p; q < len && q < p + 40; q++) {
            char c = rd->text[q];
            if (c == '\n') break;
            if (in_string) {
                if (c == '\\') q++;
                else if (c == '"') in_string = false;
            } else if (c == '"') {
                in_string = true;
            } else if (c == '[' || c == '{') {
                depth++;
            } else if ((c == ']' || c == '}') && --depth == 0) {
                copy_source(rd, p, q + 1, 40, "", buf, size);
                return buf;
            }
        }
        int n = cJSON_GetArraySize(it);
        snprintf(buf, size, "an array of %d element%s", n, n == 1 ? "" : "s");
        return buf;
    }
    if (cJSON_IsString(it)) return describe_string(rd, p, buf, size);
    size_t q = p;
    while (q < len && is_word_char(rd->text[q])) q++;
    copy_source(rd, p, q, 40, "...", buf, size);
    return buf;
}

/// A key as the file spells it, with its quotes.
const char *jr_key_source(const json_reader *rd, uint32_t key_tok, char *buf, size_t size) {
    return describe_string(rd, jr_offset(rd, key_tok), buf, size);
}

static bool kinds_agree(const cJSON *it, json_kind k) {
    switch (k) {
    case JSON_OBJECT: return cJSON_IsObject(it);
    case JSON_ARRAY: return cJSON_IsArray(it);
    case JSON_STRING: return cJSON_IsString(it) && it->valuestring;
    case JSON_NUMBER: return cJSON_IsNumber(it);
    case JSON_TRUE: return cJSON_IsTrue(it);
    case JSON_FALSE: return cJSON_IsFalse(it);
    case JSON_NULL: return cJSON_IsNull(it);
    }
    return false;
}

bool jr_root(json_reader *rd, const cJSON *root, jr_val *out) {
    if (rd->ix->count == 0 || !kinds_agree(root, (json_kind)rd->ix->tok[0].kind)) return jr_fail_internal(rd, 0);
    *out = (jr_val){root, 0};
    return true;
}

jr_iter jr_iter_begin(const json_reader *rd, jr_val container) {
    return (jr_iter){container.item->child, container.tok + 1, rd->ix->tok[container.tok].next,
                   cJSON_IsObject(container.item)};
}

// 1 with the next value (and for objects its key token), 0 at the end, -1 (message written) on disagreement.
int jr_iter_next(json_reader *rd, jr_iter *it, uint32_t *key_tok, jr_val *val) {
    bool items_left = it->item != NULL, toks_left = it->tok < it->end;
    if (!items_left && !toks_left) return 0;
    uint32_t t = it->tok;
    if (items_left != toks_left) return jr_fail_internal(rd, t), -1;
    if (it->object) {
        if (rd->ix->tok[t].kind != JSON_STRING || !it->item->string || t + 1 >= it->end)
            return jr_fail_internal(rd, t), -1;
        if (key_tok) *key_tok = t;
        t++;
    }
    if (!kinds_agree(it->item, (json_kind)rd->ix->tok[t].kind)) return jr_fail_internal(rd, t), -1;
    *val = (jr_val){it->item, t};
    it->tok = rd->ix->tok[t].next;
    it->item = it->item->next;
    return 1;
}

// ---------------------------------------------------------------------------------------------
// Objects with a fixed set of keys

static bool in_list(const char *const *list, const char *s) {
    for (; *list; list++)
        if (strcmp(*list, s) == 0) return true;
    return false;
}

// "a, b, c" (plain) or "\"a\", \"b\" or \"c\"" (quoted) from a table whose entries begin with their name.
static void list_names(const void *table, size_t count, size_t stride, bool quoted, char *buf, size_t size) {
    size_t n = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < count && n < size; i++) {
        const char *name = *(const char *const *)(const void *)((const char *)table + i * stride);
        const char *sep = i == 0 ? "" : (quoted && i + 1 == count ? " or " : ", ");
        int w = snprintf(buf + n, size - n, quoted ? "%s\"%s\"" : "%s%s", sep, name);
        if (w < 0) break;
        n += (size_t)w;
    }
}

static size_t list_count(const char *const *list) {
    size_t n = 0;
    while (list[n]) n++;
    return n;
}

static bool fail_not_object(json_reader *rd, jr_val v, const char *what) {
    char got[96];
    return jr_fail_at(rd, jr_offset(rd, v.tok), "%s must be a JSON object, got %s", what,
                      jr_describe(rd, v, got, sizeof got));
}

/// Checks v is an object whose keys all belong to `keys` (NULL-terminated), each at most once.
bool jr_open(json_reader *rd, jr_val v, const char *what, const char *const *keys, jr_obj *o) {
    if (!cJSON_IsObject(v.item)) return fail_not_object(rd, v, what);
    o->self = v;
    o->what = what;
    o->count = 0;
    jr_iter it = jr_iter_begin(rd, v);
    uint32_t kt = 0;
    jr_val val;
    int r;
    while ((r = jr_iter_next(rd, &it, &kt, &val)) > 0) {
        const char *key = val.item->string;
        char src[96], list[512];
        if (!in_list(keys, key)) {
            list_names(keys, list_count(keys), sizeof *keys, false, list, sizeof list);
            return jr_fail_at(rd, jr_offset(rd, kt), "unknown key %s in %s; expected one of: %s",
                              jr_key_source(rd, kt, src, sizeof src), what, list);
        }
        for (size_t i = 0; i < o->count; i++) {
            if (strcmp(o->m[i].key, key) != 0) continue;
            if (rd->call) // no position in a value a program passed means anything to it
                return jr_fail_at(rd, 0, "duplicate key %s in %s", jr_key_source(rd, kt, src, sizeof src), what);
            size_t line, col;
            json_line_col(rd->text, rd->len, jr_offset(rd, o->m[i].key_tok), &line, &col);
            return jr_fail_at(rd, jr_offset(rd, kt), "duplicate key %s in %s (first given at %zu:%zu)",
                              jr_key_source(rd, kt, src, sizeof src), what, line, col);
        }
        if (o->count == JR_MAX_KEYS) return jr_fail_internal(rd, kt);
        o->m[o->count++] = (jr_member){key, kt, val};
    }
    return r == 0;
}

const jr_member *jr_get(const jr_obj *o, const char *key) {
    for (size_t i = 0; i < o->count; i++)
        if (strcmp(o->m[i].key, key) == 0) return &o->m[i];
    return NULL;
}

static bool fail_missing(json_reader *rd, const jr_obj *o, const char *key) {
    return jr_fail_at(rd, jr_offset(rd, o->self.tok), "missing required key \"%s\" in %s", key, o->what);
}

// The value to point at for a problem with `key`: the key's value if given, else the whole object.
size_t jr_member_offset(const json_reader *rd, const jr_obj *o, const char *key) {
    const jr_member *m = jr_get(o, key);
    return jr_offset(rd, m ? m->val.tok : o->self.tok);
}

/// Index of `s` in a table whose entries begin with their name, or `count`.
size_t jr_find_name(const void *table, size_t count, size_t stride, const char *s) {
    for (size_t i = 0; i < count; i++)
        if (strcmp(*(const char *const *)(const void *)((const char *)table + i * stride), s) == 0) return i;
    return count;
}

/// Reads the required "type" of object v, one of the names of `table`; `what` names v in messages.
bool jr_open_typed(json_reader *rd, jr_val v, const char *what, const void *table, size_t count, size_t stride,
                       size_t *type) {
    if (!cJSON_IsObject(v.item)) return fail_not_object(rd, v, what);
    char names[256], got[96];
    list_names(table, count, stride, true, names, sizeof names);
    jr_iter it = jr_iter_begin(rd, v);
    jr_val val;
    int r;
    while ((r = jr_iter_next(rd, &it, NULL, &val)) > 0) {
        if (strcmp(val.item->string, "type") != 0) continue;
        if (cJSON_IsString(val.item) && (*type = jr_find_name(table, count, stride, val.item->valuestring)) < count)
            return true;
        return jr_fail_at(rd, jr_offset(rd, val.tok), "\"type\" must be %s, got %s", names,
                          jr_describe(rd, val, got, sizeof got));
    }
    if (r < 0) return false;
    return jr_fail_at(rd, jr_offset(rd, v.tok), "missing required key \"type\" in %s; expected one of %s", what, names);
}

// ---------------------------------------------------------------------------------------------
// Numbers, vectors, colours, flags and names

const jr_numspec JR_FINITE = {-INFINITY, INFINITY, JR_FLOAT, "a finite number"};
const jr_numspec JR_UNIT = {0.0, 1.0, JR_FLOAT, "a number in [0, 1]"};
const jr_numspec JR_NONNEG = {0.0, INFINITY, JR_FLOAT, "a finite number >= 0"};
const jr_numspec JR_POSITIVE = {0.0, INFINITY, JR_FLOAT | JR_LO_OPEN, "a finite number > 0"};
const jr_numspec JR_NONZERO_FINITE = {-INFINITY, INFINITY, JR_FLOAT | JR_NONZERO, "a finite non-zero number"};
// The paper's viewport camera keeps double precision: its image is reproduced to the pixel.
const jr_numspec JR_FINITE_DOUBLE = {-INFINITY, INFINITY, JR_FLOAT_RANGE, "a finite number"};
const jr_numspec JR_POSITIVE_DOUBLE = {0.0, INFINITY, JR_FLOAT_RANGE | JR_LO_OPEN, "a finite number > 0"};

static bool in_range(const jr_numspec *sp, double x) {
    if ((sp->flags & JR_LO_OPEN) ? !(x > sp->lo) : !(x >= sp->lo)) return false;
    return (sp->flags & JR_HI_OPEN) ? x < sp->hi : x <= sp->hi;
}

static bool number_fits(const jr_numspec *sp, double *v) {
    double x = *v;
    if (!isfinite(x)) return false;
    if ((sp->flags & (JR_FLOAT | JR_FLOAT_RANGE)) && fabs(x) > FLT_MAX) return false;
    if (!in_range(sp, x)) return false; // the number as written
    if (sp->flags & JR_FLOAT) {
        // The nearest float may lie just outside a range the number is inside (1e30 rounds up, 0.99999999 to 1):
        // then the float next to it, on the number's side, which is inside.
        float f = (float)x;
        if (!in_range(sp, f)) f = nextafterf(f, x < (double)f ? -INFINITY : INFINITY);
        if (!in_range(sp, f)) return false;
        x = f;
    }
    if ((sp->flags & JR_NONZERO) && x == 0.0) return false;
    *v = x;
    return true;
}

// "\"albedo\"" or "\"albedo\"[1]" for messages about a value or one element of it.
static const char *param_name(const char *key, int index, char *buf, size_t size) {
    if (index < 0) snprintf(buf, size, "\"%s\"", key);
    else snprintf(buf, size, "\"%s\"[%d]", key, index);
    return buf;
}

bool jr_check_number(json_reader *rd, jr_val v, const char *key, int index, const jr_numspec *sp, double *out) {
    double x = cJSON_IsNumber(v.item) ? v.item->valuedouble : NAN;
    if (number_fits(sp, &x)) {
        *out = x;
        return true;
    }
    char name[96], got[96];
    return jr_fail_at(rd, jr_offset(rd, v.tok), "%s must be %s, got %s", param_name(key, index, name, sizeof name),
                      sp->desc, jr_describe(rd, v, got, sizeof got));
}

// Exactly n numbers in an array; `shape` completes "must be an array of ...", e.g. "3 numbers (x, y, z)".
bool jr_check_numbers(json_reader *rd, jr_val v, const char *key, size_t n, const char *shape, const jr_numspec *sp,
                          double *out) {
    char got[96];
    if (!cJSON_IsArray(v.item) || (size_t)cJSON_GetArraySize(v.item) != n)
        return jr_fail_at(rd, jr_offset(rd, v.tok), "\"%s\" must be an array of %s, got %s", key, shape,
                          jr_describe(rd, v, got, sizeof got));
    jr_iter it = jr_iter_begin(rd, v);
    jr_val e;
    int r;
    for (size_t i = 0; (r = jr_iter_next(rd, &it, NULL, &e)) > 0; i++)
        if (i >= n || !jr_check_number(rd, e, key, (int)i, sp, &out[i])) return i >= n ? jr_fail_internal(rd, e.tok) : false;
    return r == 0;
}

bool jr_check_vec3(json_reader *rd, jr_val v, const char *key, const jr_numspec *sp, vec3 *out) {
    double d[3];
    if (!jr_check_numbers(rd, v, key, 3, "3 numbers (x, y, z)", sp, d)) return false;
    *out = v3((float)d[0], (float)d[1], (float)d[2]);
    return true;
}

/// A colour: one number (grey) or [r, g, b], every component as `sp` says.
bool jr_check_color(json_reader *rd, jr_val v, const char *key, const jr_numspec *sp, vec3 *out) {
    double d[3];
    if (cJSON_IsArray(v.item) && cJSON_GetArraySize(v.item) == 3) {
        if (!jr_check_numbers(rd, v, key, 3, "3 numbers", sp, d)) return false;
        *out = v3((float)d[0], (float)d[1], (float)d[2]);
        return true;
    }
    double x = cJSON_IsNumber(v.item) ? v.item->valuedouble : NAN;
    if (cJSON_IsNumber(v.item) && number_fits(sp, &x)) {
        *out = v3s((float)x);
        return true;
    }
    char got[96];
    return jr_fail_at(rd, jr_offset(rd, v.tok), "\"%s\" must be %s or an array of 3 such numbers [r, g, b], got %s", key,
                      sp->desc, jr_describe(rd, v, got, sizeof got));
}

// The member readers: an absent optional key leaves *out as it is (the default); an absent
// required key is an error naming the object.
bool jr_lookup(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_member **m) {
    *m = jr_get(o, key);
    return *m || !required || fail_missing(rd, o, key);
}

bool jr_read_float(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp, float *out) {
    const jr_member *m;
    double d;
    if (!jr_lookup(rd, o, key, required, &m)) return false;
    if (!m) return true;
    if (!jr_check_number(rd, m->val, key, -1, sp, &d)) return false;
    *out = (float)d;
    return true;
}

bool jr_read_double(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp, double *out) {
    const jr_member *m;
    if (!jr_lookup(rd, o, key, required, &m)) return false;
    return !m || jr_check_number(rd, m->val, key, -1, sp, out);
}

/// Whether the JSON number at s (the text ends at end) is exactly the integer x: its significant digits, with
/// trailing zeros moved into the exponent, followed by that many zeros, spell x.
static bool spells_integer(const char *s, const char *end, long long x) {
    bool neg = s < end && *s == '-';
    if (neg) s++;
    char digits[24];
    size_t n = 0;
    long long exp10 = 0;
    bool fraction = false;
    for (; s < end && ((*s >= '0' && *s <= '9') || *s == '.'); s++) {
        if (*s == '.') {
            fraction = true;
            continue;
        }
        if (fraction) exp10--;
        if (n == 0 && *s == '0') continue; // leading zeros
        if (n == sizeof digits) return false; // more significant digits than any long long has
        digits[n++] = *s;
    }
    if (s < end && (*s == 'e' || *s == 'E')) {
        s++;
        bool eneg = s < end && *s == '-';
        if (s < end && (*s == '-' || *s == '+')) s++;
        long long e = 0;
        for (; s < end && *s >= '0' && *s <= '9'; s++)
            if (e < 1000) e = e * 10 + (*s - '0');
        exp10 += eneg ? -e : e;
    }
    while (n > 0 && digits[n - 1] == '0') { // trailing zeros of the digits are a power of ten
        n--;
        exp10++;
    }
    if (n == 0) return x == 0;
    if (exp10 < 0 || (long long)n + exp10 > 20 || neg != (x < 0)) return false;
    char want[24], got[24 + 21];
    snprintf(want, sizeof want, "%llu", x < 0 ? 0ULL - (unsigned long long)x : (unsigned long long)x);
    memcpy(got, digits, n);
    memset(got + n, '0', (size_t)exp10);
    got[n + (size_t)exp10] = '\0';
    return strcmp(want, got) == 0;
}

bool jr_read_int(json_reader *rd, const jr_obj *o, const char *key, bool required, long long lo, long long hi,
                     long long *out) {
    const jr_member *m;
    if (!jr_lookup(rd, o, key, required, &m)) return false;
    if (!m) return true;
    const cJSON *it = m->val.item;
    double x = cJSON_IsNumber(it) ? it->valuedouble : NAN;
    // Integral and in range; both bounds are exact in double (|hi| <= 2^53). The double is the number rounded,
    // so the text must say that integer exactly: 9007199254740993 rounds to 2^53, 1.0000000000000001 to 1.
    if (isfinite(x) && x == floor(x) && x >= (double)lo && x <= (double)hi &&
        spells_integer(rd->text + jr_offset(rd, m->val.tok), rd->text + rd->len, (long long)x)) {
        *out = (long long)x;
        return true;
    }
    char got[96];
    return jr_fail_at(rd, jr_offset(rd, m->val.tok), "\"%s\" must be an integer in [%lld, %lld], got %s", key, lo, hi,
                      jr_describe(rd, m->val, got, sizeof got));
}

bool jr_read_vec3(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp, vec3 *out) {
    const jr_member *m;
    if (!jr_lookup(rd, o, key, required, &m)) return false;
    return !m || jr_check_vec3(rd, m->val, key, sp, out);
}

bool jr_read_color(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp, vec3 *out) {
    const jr_member *m;
    if (!jr_lookup(rd, o, key, required, &m)) return false;
    return !m || jr_check_color(rd, m->val, key, sp, out);
}

bool jr_read_bool(json_reader *rd, const jr_obj *o, const char *key, bool *out) {
    const jr_member *m;
    if (!jr_lookup(rd, o, key, false, &m)) return false;
    if (!m) return true;
    if (cJSON_IsBool(m->val.item)) {
        *out = cJSON_IsTrue(m->val.item);
        return true;
    }
    char got[96];
    return jr_fail_at(rd, jr_offset(rd, m->val.tok), "\"%s\" must be true or false, got %s", key,
                      jr_describe(rd, m->val, got, sizeof got));
}

/// One of the strings `names` (count of them); *out is its index.
static bool check_enum(json_reader *rd, jr_val v, const char *key, const char *const *names, size_t count, int *out) {
    size_t i = cJSON_IsString(v.item) ? jr_find_name(names, count, sizeof *names, v.item->valuestring) : count;
    if (i < count) {
        *out = (int)i;
        return true;
    }
    char list[256], got[96];
    list_names(names, count, sizeof *names, true, list, sizeof list);
    return jr_fail_at(rd, jr_offset(rd, v.tok), "\"%s\" must be %s, got %s", key, list, jr_describe(rd, v, got, sizeof got));
}

bool jr_read_enum(json_reader *rd, const jr_obj *o, const char *key, const char *const *names, size_t count, int *out) {
    const jr_member *m;
    if (!jr_lookup(rd, o, key, false, &m)) return false;
    return !m || check_enum(rd, m->val, key, names, count, out);
}

