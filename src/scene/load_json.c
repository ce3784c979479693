// load_json.c — the strict JSON scene reader: a scene file becomes a glint_scene, or one message
// "file:line:col: what is wrong, what was expected" (docs/scene-format.md documents every key).
//
// json_scan checks the syntax and records where every value starts; cJSON builds the tree and
// unescapes strings. Both list values in document order, so the reader walks the cJSON tree and the
// token index side by side (jval = node + token) and can point at any value it rejects.
#include "core/array.h"
#include "core/filepath.h"
#include "core/strmap.h"
#include "io/image_read.h"
#include "io/json_scan.h"
#include "io/obj.h"
#include "scene/scene.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum {
    LOAD_MAX_FILE_BYTES = 256 << 20, ///< larger scene files are refused before parsing
    LOAD_MAX_ITEMS = 10000000,       ///< at most this many objects, materials and lights each
    LOAD_MAX_KEYS = 16,              ///< keys a typed object may have (every key list is shorter)
    LOAD_LIST_NAMES = 10,            ///< material names listed in an "is not defined" message
    LOAD_MAX_WARNINGS = 100,         ///< warnings kept in the scene; the rest are counted in one more
    LOAD_MAX_NOISE_DEPTH = 32,       ///< octaves of turbulence (2^32 p is already far beyond any detail)
};

// ---------------------------------------------------------------------------------------------
// Reader state, values and messages

/// A value: its cJSON node and its token in the position index.
typedef struct jval {
    const cJSON *item;
    uint32_t tok;
} jval;

/// A name defined in "materials" or "textures".
typedef struct named {
    const char *name; ///< owned by the cJSON tree, alive while the scene is read
    uint32_t index;   ///< the scene material or texture
    uint32_t tok;     ///< where it is defined
} named;

/// Name -> material or texture index, so that resolving references stays linear in the scene size.
typedef struct name_table {
    strmap map;  ///< name -> position in list
    named *list; ///< in definition order, for listing names in messages
    size_t count, cap;
} name_table;

/// The identity of a file (device and inode): two spellings of one path are the same file.
typedef struct file_id {
    dev_t dev;
    ino_t ino;
} file_id;

/// A mesh file already loaded: placing it again adds an instance, not a copy.
typedef struct mesh_entry {
    file_id id;
    bool face_normals; ///< the mesh's normals depend on this, so it is part of the key
    bool needs_fallback; ///< some faces have no material of their own (the grey fallback)
    bool warned;       ///< the missing-material warning was given
    uint32_t mesh;
} mesh_entry;

/// An image file already decoded into a texture.
typedef struct image_entry {
    file_id id;
    uint32_t texture;
} image_entry;

typedef struct loader {
    const char *name; ///< file name for messages
    const char *text;
    size_t len;
    const json_index *ix;
    glint_scene *scene;
    glint_error *err;
    glint_status status; ///< GLINT_ERR_INPUT, or GLINT_ERR_RENDER when memory ran out
    name_table materials;
    name_table textures;
    mesh_entry *meshes;
    size_t mesh_count, mesh_cap;
    image_entry *images;
    size_t image_count, image_cap;
    long fallback_material;  ///< the grey Lambertian of faces without a material, once created; else -1
    size_t warnings_dropped; ///< warnings past LOAD_MAX_WARNINGS
    bool warning_oom;        ///< a warning could not be stored
} loader;

static size_t offset_of(const loader *ld, uint32_t tok) { return ld->ix->tok[tok].offset; }

#if defined(__GNUC__)
#define LOAD_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define LOAD_PRINTF(fmt, args)
#endif

// Writes "name:line:col: message" for the byte at `offset`; returns false so callers can `return fail_at(...)`.
LOAD_PRINTF(3, 4) static bool fail_at(loader *ld, size_t offset, const char *fmt, ...) {
    size_t line, col;
    json_line_col(ld->text, ld->len, offset, &line, &col);
    char *msg = ld->err->message;
    size_t size = sizeof ld->err->message;
    int n = snprintf(msg, size, "%s:%zu:%zu: ", ld->name, line, col);
    if (n >= 0 && (size_t)n < size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg + n, size - (size_t)n, fmt, ap);
        va_end(ap);
    }
    ld->status = GLINT_ERR_INPUT;
    return false;
}

static bool fail_oom(loader *ld) {
    snprintf(ld->err->message, sizeof ld->err->message, "%s: out of memory while reading the scene", ld->name);
    ld->status = GLINT_ERR_RENDER;
    return false;
}

static bool fail_internal(loader *ld, uint32_t tok) {
    size_t off = tok < ld->ix->count ? offset_of(ld, tok) : ld->len;
    return fail_at(ld, off, "internal error: the JSON scanner and cJSON disagree about this value");
}

static bool is_word_char(char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '+' || c == '-' ||
           c == '.' || c == '_';
}

// Copies source text [from, to) into buf, cut at `limit` bytes on a UTF-8 boundary with `ellipsis` added.
static void copy_source(const loader *ld, size_t from, size_t to, size_t limit, const char *ellipsis, char *buf,
                        size_t size) {
    size_t n = to - from;
    bool cut = n > limit;
    if (cut) {
        n = limit;
        while (n > 0 && ((unsigned char)ld->text[from + n] & 0xC0u) == 0x80u) n--;
    }
    snprintf(buf, size, "%.*s%s", (int)n, ld->text + from, cut ? ellipsis : "");
}

/// The string whose opening quote is at p as the file spells it, quotes included, cut after 40 bytes.
static const char *describe_string(const loader *ld, size_t p, char *buf, size_t size) {
    size_t q = p + 1, len = ld->len;
    while (q < len && ld->text[q] != '"') q += ld->text[q] == '\\' ? 2 : 1;
    if (q > len) q = len;
    if (q - p > 40) copy_source(ld, p, q, 40, "...\"", buf, size);
    else copy_source(ld, p, q < len ? q + 1 : len, 41, "", buf, size);
    return buf;
}

/// The value as the file spells it, for "got ..." clauses: "abc", 1e999, [1, 2], or "an object".
static const char *describe(const loader *ld, jval v, char *buf, size_t size) {
    size_t p = offset_of(ld, v.tok), len = ld->len;
    const cJSON *it = v.item;
    if (cJSON_IsObject(it)) return "an object";
    if (cJSON_IsArray(it)) {
        // Short one-line arrays are quoted as written; others are summarised.
        int depth = 0;
        bool in_string = false;
        for (size_t q = p; q < len && q < p + 40; q++) {
            char c = ld->text[q];
            if (c == '\n') break;
            if (in_string) {
                if (c == '\\') q++;
                else if (c == '"') in_string = false;
            } else if (c == '"') {
                in_string = true;
            } else if (c == '[' || c == '{') {
                depth++;
            } else if ((c == ']' || c == '}') && --depth == 0) {
                copy_source(ld, p, q + 1, 40, "", buf, size);
                return buf;
            }
        }
        int n = cJSON_GetArraySize(it);
        snprintf(buf, size, "an array of %d element%s", n, n == 1 ? "" : "s");
        return buf;
    }
    if (cJSON_IsString(it)) return describe_string(ld, p, buf, size);
    size_t q = p;
    while (q < len && is_word_char(ld->text[q])) q++;
    copy_source(ld, p, q, 40, "...", buf, size);
    return buf;
}

/// A key as the file spells it, with its quotes.
static const char *key_source(const loader *ld, uint32_t key_tok, char *buf, size_t size) {
    return describe_string(ld, offset_of(ld, key_tok), buf, size);
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

/// Walks the members of an object or the elements of an array, in step with the token index.
typedef struct jiter {
    const cJSON *item;
    uint32_t tok, end;
    bool object;
} jiter;

static jiter iter_begin(const loader *ld, jval container) {
    return (jiter){container.item->child, container.tok + 1, ld->ix->tok[container.tok].next,
                   cJSON_IsObject(container.item)};
}

// 1 with the next value (and for objects its key token), 0 at the end, -1 (message written) on disagreement.
static int iter_step(loader *ld, jiter *it, uint32_t *key_tok, jval *val) {
    bool items_left = it->item != NULL, toks_left = it->tok < it->end;
    if (!items_left && !toks_left) return 0;
    uint32_t t = it->tok;
    if (items_left != toks_left) return fail_internal(ld, t), -1;
    if (it->object) {
        if (ld->ix->tok[t].kind != JSON_STRING || !it->item->string || t + 1 >= it->end)
            return fail_internal(ld, t), -1;
        if (key_tok) *key_tok = t;
        t++;
    }
    if (!kinds_agree(it->item, (json_kind)ld->ix->tok[t].kind)) return fail_internal(ld, t), -1;
    *val = (jval){it->item, t};
    it->tok = ld->ix->tok[t].next;
    it->item = it->item->next;
    return 1;
}

// ---------------------------------------------------------------------------------------------
// Objects with a fixed set of keys

/// A key the object may have, found in the file.
typedef struct jmember {
    const char *key; ///< unescaped
    uint32_t key_tok;
    jval val;
} jmember;

/// An object whose keys were all checked against a list: no unknown and no repeated key.
typedef struct jobj {
    jval self;
    const char *what; ///< "render", "object 3 (sphere)", ... for messages
    size_t count;
    jmember m[LOAD_MAX_KEYS];
} jobj;

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

static bool fail_not_object(loader *ld, jval v, const char *what) {
    char got[96];
    return fail_at(ld, offset_of(ld, v.tok), "%s must be a JSON object, got %s", what,
                   describe(ld, v, got, sizeof got));
}

/// Checks v is an object whose keys all belong to `keys` (NULL-terminated), each at most once.
static bool obj_open(loader *ld, jval v, const char *what, const char *const *keys, jobj *o) {
    if (!cJSON_IsObject(v.item)) return fail_not_object(ld, v, what);
    o->self = v;
    o->what = what;
    o->count = 0;
    jiter it = iter_begin(ld, v);
    uint32_t kt = 0;
    jval val;
    int r;
    while ((r = iter_step(ld, &it, &kt, &val)) > 0) {
        const char *key = val.item->string;
        char src[96], list[512];
        if (!in_list(keys, key)) {
            list_names(keys, list_count(keys), sizeof *keys, false, list, sizeof list);
            return fail_at(ld, offset_of(ld, kt), "unknown key %s in %s; expected one of: %s",
                           key_source(ld, kt, src, sizeof src), what, list);
        }
        for (size_t i = 0; i < o->count; i++) {
            if (strcmp(o->m[i].key, key) != 0) continue;
            size_t line, col;
            json_line_col(ld->text, ld->len, offset_of(ld, o->m[i].key_tok), &line, &col);
            return fail_at(ld, offset_of(ld, kt), "duplicate key %s in %s (first given at %zu:%zu)",
                           key_source(ld, kt, src, sizeof src), what, line, col);
        }
        if (o->count == LOAD_MAX_KEYS) return fail_internal(ld, kt);
        o->m[o->count++] = (jmember){key, kt, val};
    }
    return r == 0;
}

static const jmember *obj_get(const jobj *o, const char *key) {
    for (size_t i = 0; i < o->count; i++)
        if (strcmp(o->m[i].key, key) == 0) return &o->m[i];
    return NULL;
}

static bool fail_missing(loader *ld, const jobj *o, const char *key) {
    return fail_at(ld, offset_of(ld, o->self.tok), "missing required key \"%s\" in %s", key, o->what);
}

// The value to point at for a problem with `key`: the key's value if given, else the whole object.
static size_t offset_of_member(const loader *ld, const jobj *o, const char *key) {
    const jmember *m = obj_get(o, key);
    return offset_of(ld, m ? m->val.tok : o->self.tok);
}

/// Index of `s` in a table whose entries begin with their name, or `count`.
static size_t find_name(const void *table, size_t count, size_t stride, const char *s) {
    for (size_t i = 0; i < count; i++)
        if (strcmp(*(const char *const *)(const void *)((const char *)table + i * stride), s) == 0) return i;
    return count;
}

/// Reads the required "type" of object v, one of the names of `table`; `what` names v in messages.
static bool open_typed(loader *ld, jval v, const char *what, const void *table, size_t count, size_t stride,
                       size_t *type) {
    if (!cJSON_IsObject(v.item)) return fail_not_object(ld, v, what);
    char names[256], got[96];
    list_names(table, count, stride, true, names, sizeof names);
    jiter it = iter_begin(ld, v);
    jval val;
    int r;
    while ((r = iter_step(ld, &it, NULL, &val)) > 0) {
        if (strcmp(val.item->string, "type") != 0) continue;
        if (cJSON_IsString(val.item) && (*type = find_name(table, count, stride, val.item->valuestring)) < count)
            return true;
        return fail_at(ld, offset_of(ld, val.tok), "\"type\" must be %s, got %s", names,
                       describe(ld, val, got, sizeof got));
    }
    if (r < 0) return false;
    return fail_at(ld, offset_of(ld, v.tok), "missing required key \"type\" in %s; expected one of %s", what, names);
}

// ---------------------------------------------------------------------------------------------
// Numbers, vectors, colours, flags and names

/// The numbers a parameter accepts; desc says so in messages ("a number in [0, 1]").
typedef struct numspec {
    double lo, hi;
    unsigned flags;
    const char *desc;
} numspec;

enum {
    NUM_LO_OPEN = 1u, ///< lo itself is excluded
    NUM_HI_OPEN = 2u, ///< hi itself is excluded
    NUM_NONZERO = 4u,
    NUM_FLOAT = 8u,   ///< stored as float: checks apply to the value after rounding to float
    NUM_FLOAT_RANGE = 16u, ///< kept in double, but within float range (it is converted at some point)
};

static const numspec NUM_FINITE = {-INFINITY, INFINITY, NUM_FLOAT, "a finite number"};
static const numspec NUM_UNIT = {0.0, 1.0, NUM_FLOAT, "a number in [0, 1]"};
static const numspec NUM_NONNEG = {0.0, INFINITY, NUM_FLOAT, "a finite number >= 0"};
static const numspec NUM_POSITIVE = {0.0, INFINITY, NUM_FLOAT | NUM_LO_OPEN, "a finite number > 0"};
static const numspec NUM_NONZERO_FINITE = {-INFINITY, INFINITY, NUM_FLOAT | NUM_NONZERO, "a finite non-zero number"};
static const numspec NUM_VFOV = {0.0, 180.0, NUM_FLOAT | NUM_LO_OPEN | NUM_HI_OPEN, "a number in (0, 180)"};
static const numspec NUM_DEFOCUS = {0.0, 180.0, NUM_FLOAT | NUM_HI_OPEN, "a number in [0, 180)"};
// The paper's viewport camera keeps double precision: its image is reproduced to the pixel.
static const numspec NUM_FINITE_DOUBLE = {-INFINITY, INFINITY, NUM_FLOAT_RANGE, "a finite number"};
static const numspec NUM_POSITIVE_DOUBLE = {0.0, INFINITY, NUM_FLOAT_RANGE | NUM_LO_OPEN, "a finite number > 0"};

static bool number_fits(const numspec *sp, double *v) {
    double x = *v;
    if (!isfinite(x)) return false;
    if ((sp->flags & (NUM_FLOAT | NUM_FLOAT_RANGE)) && fabs(x) > FLT_MAX) return false;
    if (sp->flags & NUM_FLOAT) x = (double)(float)x;
    if ((sp->flags & NUM_LO_OPEN) ? !(x > sp->lo) : !(x >= sp->lo)) return false;
    if ((sp->flags & NUM_HI_OPEN) ? !(x < sp->hi) : !(x <= sp->hi)) return false;
    if ((sp->flags & NUM_NONZERO) && x == 0.0) return false;
    *v = x;
    return true;
}

// "\"albedo\"" or "\"albedo\"[1]" for messages about a value or one element of it.
static const char *param_name(const char *key, int index, char *buf, size_t size) {
    if (index < 0) snprintf(buf, size, "\"%s\"", key);
    else snprintf(buf, size, "\"%s\"[%d]", key, index);
    return buf;
}

static bool check_number(loader *ld, jval v, const char *key, int index, const numspec *sp, double *out) {
    double x = cJSON_IsNumber(v.item) ? v.item->valuedouble : NAN;
    if (number_fits(sp, &x)) {
        *out = x;
        return true;
    }
    char name[96], got[96];
    return fail_at(ld, offset_of(ld, v.tok), "%s must be %s, got %s", param_name(key, index, name, sizeof name),
                   sp->desc, describe(ld, v, got, sizeof got));
}

// Exactly n numbers in an array; `shape` completes "must be an array of ...", e.g. "3 numbers (x, y, z)".
static bool check_numbers(loader *ld, jval v, const char *key, size_t n, const char *shape, const numspec *sp,
                          double *out) {
    char got[96];
    if (!cJSON_IsArray(v.item) || (size_t)cJSON_GetArraySize(v.item) != n)
        return fail_at(ld, offset_of(ld, v.tok), "\"%s\" must be an array of %s, got %s", key, shape,
                       describe(ld, v, got, sizeof got));
    jiter it = iter_begin(ld, v);
    jval e;
    int r;
    for (size_t i = 0; (r = iter_step(ld, &it, NULL, &e)) > 0; i++)
        if (i >= n || !check_number(ld, e, key, (int)i, sp, &out[i])) return i >= n ? fail_internal(ld, e.tok) : false;
    return r == 0;
}

static bool check_vec3(loader *ld, jval v, const char *key, const numspec *sp, vec3 *out) {
    double d[3];
    if (!check_numbers(ld, v, key, 3, "3 numbers (x, y, z)", sp, d)) return false;
    *out = v3((float)d[0], (float)d[1], (float)d[2]);
    return true;
}

/// A colour: one number (grey) or [r, g, b], every component as `sp` says.
static bool check_color(loader *ld, jval v, const char *key, const numspec *sp, vec3 *out) {
    double d[3];
    if (cJSON_IsArray(v.item) && cJSON_GetArraySize(v.item) == 3) {
        if (!check_numbers(ld, v, key, 3, "3 numbers", sp, d)) return false;
        *out = v3((float)d[0], (float)d[1], (float)d[2]);
        return true;
    }
    double x = cJSON_IsNumber(v.item) ? v.item->valuedouble : NAN;
    if (cJSON_IsNumber(v.item) && number_fits(sp, &x)) {
        *out = v3s((float)x);
        return true;
    }
    char got[96];
    return fail_at(ld, offset_of(ld, v.tok), "\"%s\" must be %s or an array of 3 such numbers [r, g, b], got %s", key,
                   sp->desc, describe(ld, v, got, sizeof got));
}

// The member readers: an absent optional key leaves *out as it is (the default); an absent
// required key is an error naming the object.
static bool get_member(loader *ld, const jobj *o, const char *key, bool required, const jmember **m) {
    *m = obj_get(o, key);
    return *m || !required || fail_missing(ld, o, key);
}

static bool read_float(loader *ld, const jobj *o, const char *key, bool required, const numspec *sp, float *out) {
    const jmember *m;
    double d;
    if (!get_member(ld, o, key, required, &m)) return false;
    if (!m) return true;
    if (!check_number(ld, m->val, key, -1, sp, &d)) return false;
    *out = (float)d;
    return true;
}

static bool read_double(loader *ld, const jobj *o, const char *key, bool required, const numspec *sp, double *out) {
    const jmember *m;
    if (!get_member(ld, o, key, required, &m)) return false;
    return !m || check_number(ld, m->val, key, -1, sp, out);
}

static bool read_int(loader *ld, const jobj *o, const char *key, bool required, long long lo, long long hi,
                     long long *out) {
    const jmember *m;
    if (!get_member(ld, o, key, required, &m)) return false;
    if (!m) return true;
    const cJSON *it = m->val.item;
    double x = cJSON_IsNumber(it) ? it->valuedouble : NAN;
    // Integral and in range; both bounds are exact in double (|hi| <= 2^53).
    if (isfinite(x) && x == floor(x) && x >= (double)lo && x <= (double)hi) {
        *out = (long long)x;
        return true;
    }
    char got[96];
    return fail_at(ld, offset_of(ld, m->val.tok), "\"%s\" must be an integer in [%lld, %lld], got %s", key, lo, hi,
                   describe(ld, m->val, got, sizeof got));
}

static bool read_vec3(loader *ld, const jobj *o, const char *key, bool required, const numspec *sp, vec3 *out) {
    const jmember *m;
    if (!get_member(ld, o, key, required, &m)) return false;
    return !m || check_vec3(ld, m->val, key, sp, out);
}

static bool read_color(loader *ld, const jobj *o, const char *key, bool required, const numspec *sp, vec3 *out) {
    const jmember *m;
    if (!get_member(ld, o, key, required, &m)) return false;
    return !m || check_color(ld, m->val, key, sp, out);
}

static bool read_bool(loader *ld, const jobj *o, const char *key, bool *out) {
    const jmember *m;
    if (!get_member(ld, o, key, false, &m)) return false;
    if (!m) return true;
    if (cJSON_IsBool(m->val.item)) {
        *out = cJSON_IsTrue(m->val.item);
        return true;
    }
    char got[96];
    return fail_at(ld, offset_of(ld, m->val.tok), "\"%s\" must be true or false, got %s", key,
                   describe(ld, m->val, got, sizeof got));
}

/// One of the strings `names` (count of them); *out is its index.
static bool check_enum(loader *ld, jval v, const char *key, const char *const *names, size_t count, int *out) {
    size_t i = cJSON_IsString(v.item) ? find_name(names, count, sizeof *names, v.item->valuestring) : count;
    if (i < count) {
        *out = (int)i;
        return true;
    }
    char list[256], got[96];
    list_names(names, count, sizeof *names, true, list, sizeof list);
    return fail_at(ld, offset_of(ld, v.tok), "\"%s\" must be %s, got %s", key, list, describe(ld, v, got, sizeof got));
}

static bool read_enum(loader *ld, const jobj *o, const char *key, const char *const *names, size_t count, int *out) {
    const jmember *m;
    if (!get_member(ld, o, key, false, &m)) return false;
    return !m || check_enum(ld, m->val, key, names, count, out);
}

// ---------------------------------------------------------------------------------------------
// The material name table

static const named *names_find(const name_table *t, const char *name) {
    size_t i;
    return strmap_get(&t->map, name, strlen(name), &i) ? &t->list[i] : NULL;
}

static bool names_add(name_table *t, const char *name, uint32_t index, uint32_t tok) {
    if (!array_reserve((void **)&t->list, &t->cap, t->count + 1, sizeof *t->list) ||
        !strmap_put(&t->map, name, strlen(name), t->count))
        return false;
    t->list[t->count++] = (named){name, index, tok};
    return true;
}

static void names_free(name_table *t) {
    strmap_free(&t->map);
    free(t->list);
}

/// Checks the key at kt as a new name for `map`: 1 to SCENE_MAX_NAME bytes, no control characters, unused.
static bool check_new_name(loader *ld, const name_table *map, uint32_t kt, const char *name, const char *kind) {
    char got[96];
    size_t n = strlen(name);
    if (n == 0 || n > SCENE_MAX_NAME)
        return fail_at(ld, offset_of(ld, kt), "%s name %s must be 1 to %d bytes long", kind,
                       key_source(ld, kt, got, sizeof got), SCENE_MAX_NAME);
    for (size_t i = 0; i < n; i++)
        if ((unsigned char)name[i] < 0x20)
            return fail_at(ld, offset_of(ld, kt), "%s name %s must not contain control characters", kind,
                           key_source(ld, kt, got, sizeof got));
    const named *prev = names_find(map, name);
    if (prev) {
        size_t line, col;
        json_line_col(ld->text, ld->len, offset_of(ld, prev->tok), &line, &col);
        return fail_at(ld, offset_of(ld, kt), "duplicate %s name \"%s\" (first defined at %zu:%zu)", kind, name, line,
                       col);
    }
    return true;
}

/// "material "blu" is not defined (defined: red, green)": lists the first few names in definition order.
static bool fail_undefined(loader *ld, jval v, const name_table *map, const char *kind) {
    char names[512], got[96];
    size_t n = 0, listed = 0;
    names[0] = '\0';
    for (size_t i = 0; i < map->count && listed < LOAD_LIST_NAMES; i++) {
        int w = snprintf(names + n, sizeof names - n, "%s%s", listed ? ", " : "", map->list[i].name);
        if (w < 0 || (size_t)w >= sizeof names - n) break;
        n += (size_t)w;
        listed++;
    }
    const char *what = describe(ld, v, got, sizeof got);
    if (map->count == 0)
        return fail_at(ld, offset_of(ld, v.tok), "%s %s is not defined (no named %ss are defined)", kind, what, kind);
    if (listed < map->count)
        return fail_at(ld, offset_of(ld, v.tok), "%s %s is not defined (defined: %s and %zu more)", kind, what, names,
                       map->count - listed);
    return fail_at(ld, offset_of(ld, v.tok), "%s %s is not defined (defined: %s)", kind, what, names);
}

// ---------------------------------------------------------------------------------------------
// Files the scene refers to (meshes, images): paths relative to the scene file's directory

/// `file` as a path usable from the current directory: absolute paths as they are, others joined to the
/// scene file's directory. NULL when out of memory.
static char *resolve_path(const loader *ld, const char *file) {
    return filepath_join(ld->name, filepath_dir_length(ld->name), file, strlen(file));
}

// " (resolved/path)" when the path opened differs from the one written, else "".
static const char *resolved_note(const char *written, const char *path, char *buf, size_t size) {
    if (strcmp(written, path) == 0) return "";
    snprintf(buf, size, " (%.400s)", path);
    return buf;
}

// Why `path` cannot be read as a file: 0 when it is a regular file (*st then holds its identity), an errno
// value, or -1 for a special file (device, FIFO, socket), which could block or never end.
static int file_problem(const char *path, struct stat *st) {
    if (stat(path, st) != 0) return errno ? errno : ENOENT;
    if (S_ISDIR(st->st_mode)) return EISDIR;
    return S_ISREG(st->st_mode) ? 0 : -1;
}

static const char *file_problem_text(int e) { return e > 0 ? strerror(e) : "not a regular file"; }

/// Reads the required path `key` of o, resolves it (*path, malloc'd) and checks that it names a regular
/// file (*id). `kind` ("mesh", "image") names the file in messages: `image file "a.png": cannot open: reason`.
static bool read_file_path(loader *ld, const jobj *o, const char *key, const char *kind, char **path, file_id *id,
                           jval *where) {
    const jmember *m;
    char got[96], note[420];
    *path = NULL;
    if (!get_member(ld, o, key, true, &m)) return false;
    jval v = *where = m->val;
    if (!cJSON_IsString(v.item) || v.item->valuestring[0] == '\0')
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"%s\" must be a non-empty string (a path relative to the scene file), got %s", key,
                       describe(ld, v, got, sizeof got));
    const char *written = v.item->valuestring;
    char *p = resolve_path(ld, written);
    if (!p) return fail_oom(ld);
    struct stat st;
    int e = file_problem(p, &st);
    if (e != 0) {
        fail_at(ld, offset_of(ld, v.tok), "%s file %s%s: cannot open: %s", kind, describe(ld, v, got, sizeof got),
                resolved_note(written, p, note, sizeof note), file_problem_text(e));
        free(p);
        return false;
    }
    *path = p;
    *id = (file_id){st.st_dev, st.st_ino};
    return true;
}

// The message of a library that starts with the path it was given, without that "path: " prefix.
static const char *strip_path(const char *message, const char *path) {
    size_t n = strlen(path);
    return strncmp(message, path, n) == 0 && message[n] == ':' && message[n + 1] == ' ' ? message + n + 2 : message;
}

/// The scene texture of image file `path` (id), decoded on first use; `where` is blamed for failures, and
/// `prefix` (may be "") opens their message.
static bool load_image(loader *ld, size_t where, const char *prefix, const char *written, const char *path,
                       file_id id, uint32_t *index) {
    for (size_t i = 0; i < ld->image_count; i++)
        if (ld->images[i].id.dev == id.dev && ld->images[i].id.ino == id.ino) {
            *index = ld->images[i].texture;
            return true;
        }
    if (ld->scene->texture_count >= LOAD_MAX_ITEMS)
        return fail_at(ld, where, "too many textures (the limit is %d)", LOAD_MAX_ITEMS);
    // The file is decoded here (io/), and the texture module only takes the pixels.
    image_rgb img;
    glint_error err;
    if (image_read(path, &img, &err) != GLINT_OK) {
        char note[420];
        return fail_at(ld, where, "%simage file \"%.300s\"%s: %s", prefix, written,
                       resolved_note(written, path, note, sizeof note), strip_path(err.message, path));
    }
    texture t = texture_image(img);
    long i = scene_add_texture(ld->scene, &t, NULL);
    if (i < 0 || !array_reserve((void **)&ld->images, &ld->image_cap, ld->image_count + 1, sizeof *ld->images))
        return fail_oom(ld);
    ld->images[ld->image_count++] = (image_entry){id, (uint32_t)i};
    *index = (uint32_t)i;
    return true;
}

// ---------------------------------------------------------------------------------------------
// Warnings: collected in the scene (the library prints nothing); the command line shows them

static void add_warning(loader *ld, const char *message) {
    if (ld->scene->warning_count >= LOAD_MAX_WARNINGS) {
        ld->warnings_dropped++;
        return;
    }
    if (!scene_add_warning(ld->scene, message)) ld->warning_oom = true;
}

// The OBJ reader's callback.
static void collect_warning(const char *message, void *user) { add_warning(user, message); }

LOAD_PRINTF(3, 4) static void warn_at(loader *ld, size_t offset, const char *fmt, ...) {
    char msg[1024];
    size_t line, col;
    json_line_col(ld->text, ld->len, offset, &line, &col);
    int n = snprintf(msg, sizeof msg, "%s:%zu:%zu: warning: ", ld->name, line, col);
    if (n >= 0 && (size_t)n < sizeof msg) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg + n, sizeof msg - (size_t)n, fmt, ap);
        va_end(ap);
    }
    add_warning(ld, msg);
}

// ---------------------------------------------------------------------------------------------
// The two shapes of a top-level collection: an object mapping names to items, an array of items

/// Reads one named ("textures", "materials") or inline item into the scene; *index is its number.
typedef bool (*named_reader)(loader *ld, jval v, const char *what, const char *name, uint32_t *index);

/// Reads "<kind>s", an object mapping names to items of that kind, adding each name to `map`.
static bool read_named(loader *ld, jval v, const char *kind, name_table *map, named_reader read) {
    char got[96], what[64 + SCENE_MAX_NAME];
    if (!cJSON_IsObject(v.item))
        return fail_at(ld, offset_of(ld, v.tok), "\"%ss\" must be a JSON object mapping names to %ss, got %s", kind,
                       kind, describe(ld, v, got, sizeof got));
    jiter it = iter_begin(ld, v);
    uint32_t kt = 0;
    jval val;
    int r;
    while ((r = iter_step(ld, &it, &kt, &val)) > 0) {
        // The key string lives in the cJSON tree for the whole parse: the map may point at it.
        const char *name = val.item->string;
        if (!check_new_name(ld, map, kt, name, kind)) return false;
        snprintf(what, sizeof what, "%s \"%s\"", kind, name);
        uint32_t index;
        if (!read(ld, val, what, name, &index)) return false;
        if (!names_add(map, name, index, kt)) return fail_oom(ld);
    }
    return r == 0;
}

/// Reads element i of an array ("objects", "lights") into the scene.
typedef bool (*element_reader)(loader *ld, jval v, size_t i);

/// Reads `key`, an array of at most LOAD_MAX_ITEMS objects.
static bool read_array(loader *ld, jval v, const char *key, element_reader read) {
    char got[96];
    if (!cJSON_IsArray(v.item))
        return fail_at(ld, offset_of(ld, v.tok), "\"%s\" must be an array of objects, got %s", key,
                       describe(ld, v, got, sizeof got));
    jiter it = iter_begin(ld, v);
    jval e;
    int r;
    for (size_t i = 0; (r = iter_step(ld, &it, NULL, &e)) > 0; i++) {
        if (i >= LOAD_MAX_ITEMS)
            return fail_at(ld, offset_of(ld, e.tok), "too many %s (the limit is %d)", key, LOAD_MAX_ITEMS);
        if (!read(ld, e, i)) return false;
    }
    return r == 0;
}

// ---------------------------------------------------------------------------------------------
// Textures: add a row to texture_types (name, keys, reader) for a new kind.

static const char *const solid_keys[] = {"type", "color", NULL};
static const char *const checker_keys[] = {"type", "scale", "even", "odd", NULL};
static const char *const noise_keys[] = {"type", "scale", "color", "seed", NULL};
static const char *const turbulence_keys[] = {"type", "scale", "depth", "color", "seed", NULL};
static const char *const image_keys[] = {"type", "file", NULL};

/// Adds the texture a texture object describes (or finds the one already loaded from the same image);
/// `name` is NULL for inline textures.
typedef bool (*texture_reader)(loader *ld, const jobj *o, int variant, const char *name, uint32_t *index);

static bool add_texture(loader *ld, const jobj *o, texture *t, const char *name, uint32_t *index) {
    if (ld->scene->texture_count >= LOAD_MAX_ITEMS) {
        texture_free(t);
        return fail_at(ld, offset_of(ld, o->self.tok), "too many textures (the limit is %d)", LOAD_MAX_ITEMS);
    }
    long i = scene_add_texture(ld->scene, t, name);
    if (i < 0) return fail_oom(ld);
    *index = (uint32_t)i;
    return true;
}

static bool read_solid(loader *ld, const jobj *o, int variant, const char *name, uint32_t *index) {
    (void)variant;
    vec3 c;
    if (!read_color(ld, o, "color", true, &NUM_NONNEG, &c)) return false;
    texture t = texture_solid(c);
    return add_texture(ld, o, &t, name, index);
}

static bool read_checker(loader *ld, const jobj *o, int variant, const char *name, uint32_t *index) {
    (void)variant;
    float scale = 1.0f;
    vec3 even = v3s(1.0f), odd = v3s(0.0f);
    if (!read_float(ld, o, "scale", false, &NUM_POSITIVE, &scale) ||
        !read_color(ld, o, "even", false, &NUM_NONNEG, &even) || !read_color(ld, o, "odd", false, &NUM_NONNEG, &odd))
        return false;
    // The checker divides by the scale: a subnormal one would overflow 1/scale.
    if (!isfinite(1.0f / scale)) {
        const jmember *m = obj_get(o, "scale");
        char got[96];
        return fail_at(ld, offset_of(ld, m->val.tok), "\"scale\" must be at least %g, got %s", (double)FLT_MIN,
                       describe(ld, m->val, got, sizeof got));
    }
    texture t = texture_checker(scale, even, odd);
    return add_texture(ld, o, &t, name, index);
}

static bool read_noise(loader *ld, const jobj *o, int variant, const char *name, uint32_t *index) {
    float scale = 1.0f;
    vec3 color = v3s(1.0f);
    long long depth = 7, seed = 0;
    if (!read_float(ld, o, "scale", false, &NUM_POSITIVE, &scale) ||
        !read_int(ld, o, "depth", false, 1, LOAD_MAX_NOISE_DEPTH, &depth) ||
        !read_color(ld, o, "color", false, &NUM_NONNEG, &color) ||
        !read_int(ld, o, "seed", false, 0, 9007199254740992LL, &seed))
        return false;
    texture t;
    if (!texture_noise((noise_kind)variant, scale, (int)depth, color, (uint64_t)seed, &t)) return fail_oom(ld);
    return add_texture(ld, o, &t, name, index);
}

static bool read_image(loader *ld, const jobj *o, int variant, const char *name, uint32_t *index) {
    (void)variant;
    char *path;
    file_id id;
    jval where;
    if (!read_file_path(ld, o, "file", "image", &path, &id, &where)) return false;
    size_t before = ld->scene->texture_count;
    bool ok = load_image(ld, offset_of(ld, where.tok), "", where.item->valuestring, path, id, index);
    free(path);
    // A newly decoded image takes the name it was first defined under (an image given twice loads once).
    if (ok && name && ld->scene->texture_count > before && !ld->scene->texture_names[*index]) {
        size_t n = strlen(name) + 1;
        char *copy = malloc(n);
        if (!copy) return fail_oom(ld);
        memcpy(copy, name, n);
        ld->scene->texture_names[*index] = copy;
    }
    return ok;
}

static const struct texture_type {
    const char *name;
    const char *const *keys;
    texture_reader read;
    int variant; ///< noise: its noise_kind
} texture_types[] = {
    {"solid", solid_keys, read_solid, 0},
    {"checker", checker_keys, read_checker, 0},
    {"noise", noise_keys, read_noise, NOISE_PLAIN},
    {"turbulence", turbulence_keys, read_noise, NOISE_TURBULENCE},
    {"marble", turbulence_keys, read_noise, NOISE_MARBLE},
    {"image", image_keys, read_image, 0},
};
#define TEXTURE_TYPES (sizeof texture_types / sizeof texture_types[0])

/// Reads a texture object and adds it to the scene (named or anonymous); *index is its number.
static bool read_texture(loader *ld, jval v, const char *what, const char *name, uint32_t *index) {
    size_t t;
    if (!open_typed(ld, v, what, texture_types, TEXTURE_TYPES, sizeof texture_types[0], &t)) return false;
    jobj o;
    return obj_open(ld, v, what, texture_types[t].keys, &o) &&
           texture_types[t].read(ld, &o, texture_types[t].variant, name, index);
}

// The largest colour component a texture can give (images are in [0, 1]).
static float texture_peak(const texture *t) {
    vec3 c = t->kind == TEX_CHECKER ? v3_max(t->even, t->odd) : t->kind == TEX_IMAGE ? v3s(1.0f) : t->color;
    return fmaxf(c.x, fmaxf(c.y, c.z));
}

/// A material colour parameter: a number or [r, g, b] (into *color), or a texture, by name or inline (into
/// *tex). Textures used where components must be at most 1 (albedo) must not exceed 1 either.
static bool read_material_color(loader *ld, const jobj *o, const char *key, const numspec *sp, vec3 *color,
                                int32_t *tex) {
    const jmember *m = obj_get(o, key);
    if (!m) return true;
    jval v = m->val;
    char got[96];
    if (cJSON_IsNumber(v.item) || (cJSON_IsArray(v.item) && cJSON_GetArraySize(v.item) == 3))
        return check_color(ld, v, key, sp, color);
    uint32_t index;
    if (cJSON_IsString(v.item)) {
        const named *s = names_find(&ld->textures, v.item->valuestring);
        if (!s) return fail_undefined(ld, v, &ld->textures, "texture");
        index = s->index;
    } else if (cJSON_IsObject(v.item)) {
        char what[96 + SCENE_MAX_NAME];
        snprintf(what, sizeof what, "the texture \"%s\" of %s", key, o->what);
        if (!read_texture(ld, v, what, NULL, &index)) return false;
    } else {
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"%s\" must be %s, an array of 3 such numbers [r, g, b], a texture name or a texture object, "
                       "got %s",
                       key, sp->desc, describe(ld, v, got, sizeof got));
    }
    float peak = texture_peak(&ld->scene->textures[index]);
    if (peak > sp->hi)
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"%s\" must stay in [0, %g], but this texture has colour components up to %g", key, sp->hi,
                       (double)peak);
    *tex = (int32_t)index;
    return true;
}

// ---------------------------------------------------------------------------------------------
// Materials: add a row to material_types (name, kind, keys, reader) for a new kind.

static const char *const lambertian_keys[] = {"type", "albedo", NULL};
static const char *const metal_keys[] = {"type", "albedo", "fuzz", NULL};
static const char *const dielectric_keys[] = {"type", "ior", "tint", NULL};
static const char *const phong_keys[] = {"type", "color", "specular", "reflective", "specular_color", NULL};
static const char *const diffuse_light_keys[] = {"type", "emission", "two_sided", NULL};

// Every colour parameter but Phong's specular_color may be a texture (read_material_color).
static bool read_lambertian(loader *ld, const jobj *o, material *m) {
    return read_material_color(ld, o, "albedo", &NUM_UNIT, &m->albedo, &m->albedo_texture);
}

static bool read_metal(loader *ld, const jobj *o, material *m) {
    return read_material_color(ld, o, "albedo", &NUM_UNIT, &m->albedo, &m->albedo_texture) &&
           read_float(ld, o, "fuzz", false, &NUM_UNIT, &m->fuzz);
}

static bool read_dielectric(loader *ld, const jobj *o, material *m) {
    return read_float(ld, o, "ior", false, &NUM_POSITIVE, &m->ior) &&
           read_material_color(ld, o, "tint", &NUM_UNIT, &m->albedo, &m->albedo_texture);
}

static bool read_phong(loader *ld, const jobj *o, material *m) {
    long long specular = m->specular;
    if (!read_material_color(ld, o, "color", &NUM_UNIT, &m->albedo, &m->albedo_texture) ||
        !read_int(ld, o, "specular", false, -1, INT_MAX, &specular) ||
        !read_float(ld, o, "reflective", false, &NUM_UNIT, &m->reflective) ||
        !read_color(ld, o, "specular_color", false, &NUM_UNIT, &m->specular_color))
        return false;
    m->specular = (int)specular;
    m->has_specular_color = obj_get(o, "specular_color") != NULL;
    return true;
}

// A texture as "emission" scales the default emission 1: the texture's colour is the emitted radiance.
static bool read_diffuse_light(loader *ld, const jobj *o, material *m) {
    return read_material_color(ld, o, "emission", &NUM_NONNEG, &m->emission, &m->emission_texture) &&
           read_bool(ld, o, "two_sided", &m->two_sided);
}

typedef bool (*material_reader)(loader *ld, const jobj *o, material *m);

static const struct material_type {
    const char *name;
    material_kind kind;
    const char *const *keys;
    material_reader read;
} material_types[] = {
    {"lambertian", MAT_LAMBERTIAN, lambertian_keys, read_lambertian},
    {"metal", MAT_METAL, metal_keys, read_metal},
    {"dielectric", MAT_DIELECTRIC, dielectric_keys, read_dielectric},
    {"phong", MAT_PHONG, phong_keys, read_phong},
    {"diffuse_light", MAT_DIFFUSE_LIGHT, diffuse_light_keys, read_diffuse_light},
};
#define MATERIAL_TYPES (sizeof material_types / sizeof material_types[0])

/// Reads a material object and adds it to the scene (named or anonymous); *index is its number.
static bool read_material(loader *ld, jval v, const char *what, const char *name, uint32_t *index) {
    size_t t;
    if (!open_typed(ld, v, what, material_types, MATERIAL_TYPES, sizeof material_types[0], &t)) return false;
    const struct material_type *mt = &material_types[t];
    material m = material_default(mt->kind);
    jobj o;
    if (!obj_open(ld, v, what, mt->keys, &o) || !mt->read(ld, &o, &m)) return false;
    if (ld->scene->material_count >= LOAD_MAX_ITEMS)
        return fail_at(ld, offset_of(ld, v.tok), "too many materials (the limit is %d)", LOAD_MAX_ITEMS);
    long i = scene_add_material(ld->scene, &m, name);
    if (i < 0) return fail_oom(ld);
    *index = (uint32_t)i;
    return true;
}

/// The "material" of an object: a name defined in "materials", or an inline material object.
static bool read_material_ref(loader *ld, const jobj *o, const char *owner, uint32_t *index) {
    const jmember *m;
    if (!get_member(ld, o, "material", true, &m)) return false;
    jval v = m->val;
    char got[96];
    if (cJSON_IsObject(v.item)) {
        char what[96];
        snprintf(what, sizeof what, "the material of %s", owner);
        return read_material(ld, v, what, NULL, index);
    }
    if (!cJSON_IsString(v.item))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"material\" must be the name of a material in \"materials\" or a material object, got %s",
                       describe(ld, v, got, sizeof got));
    const named *s = names_find(&ld->materials, v.item->valuestring);
    if (s) {
        *index = s->index;
        return true;
    }
    return fail_undefined(ld, v, &ld->materials, "material");
}

// ---------------------------------------------------------------------------------------------
// Transforms: an array of operations, the first applied first (Mitsuba's order; pbrt's is the reverse)

static const char *const transform_op_keys[] = {"translate", "rotate", "scale", "matrix", NULL};
static const char *const rotate_keys[] = {"axis", "degrees", NULL};

// {"rotate": {"axis": [x, y, z], "degrees": a}}: right-handed, counter-clockwise looking down the axis.
static bool read_rotate(loader *ld, jval v, const char *what, mat4 *out) {
    jobj o;
    vec3 axis;
    float degrees;
    if (!obj_open(ld, v, what, rotate_keys, &o) || !read_vec3(ld, &o, "axis", true, &NUM_FINITE, &axis) ||
        !read_float(ld, &o, "degrees", true, &NUM_FINITE, &degrees))
        return false;
    if (axis.x == 0.0f && axis.y == 0.0f && axis.z == 0.0f) {
        const jmember *m = obj_get(&o, "axis");
        char got[96];
        return fail_at(ld, offset_of(ld, m->val.tok), "\"axis\" must be a non-zero vector, got %s",
                       describe(ld, m->val, got, sizeof got));
    }
    *out = mat4_rotate(axis, degrees);
    return true;
}

// {"scale": s} or {"scale": [x, y, z]}: every factor non-zero (a zero would flatten the object).
static bool read_scale(loader *ld, jval v, mat4 *out) {
    double d[3];
    if (cJSON_IsNumber(v.item)) {
        if (!check_number(ld, v, "scale", -1, &NUM_NONZERO_FINITE, &d[0])) return false;
        d[1] = d[2] = d[0];
    } else if (cJSON_IsArray(v.item) && cJSON_GetArraySize(v.item) == 3) {
        if (!check_numbers(ld, v, "scale", 3, "3 numbers", &NUM_NONZERO_FINITE, d)) return false;
    } else {
        char got[96];
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"scale\" must be a finite non-zero number or an array of 3 such numbers [x, y, z], got %s",
                       describe(ld, v, got, sizeof got));
    }
    *out = mat4_scale(v3((float)d[0], (float)d[1], (float)d[2]));
    return true;
}

// {"matrix": [16 numbers, row by row]}: affine (last row 0 0 0 1) and invertible.
static bool read_matrix(loader *ld, jval v, mat4 *out) {
    double d[16];
    if (!check_numbers(ld, v, "matrix", 16, "16 numbers (a 4x4 matrix, row by row)", &NUM_FINITE, d)) return false;
    for (int i = 0; i < 16; i++) out->m[i / 4][i % 4] = (float)d[i];
    if (!(d[12] == 0.0 && d[13] == 0.0 && d[14] == 0.0 && d[15] == 1.0))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"matrix\" must be affine: its last row must be [0, 0, 0, 1], got [%g, %g, %g, %g]", d[12],
                       d[13], d[14], d[15]);
    mat4 inv;
    if (!mat4_invert(out, &inv))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"matrix\" is singular (determinant %g); expected an invertible matrix", mat4_linear_det(out));
    return true;
}

/// Reads the optional "transform" of o into *xf (object to world); *given is false without one.
static bool read_transform(loader *ld, const jobj *o, transform *xf, bool *given) {
    const jmember *m = obj_get(o, "transform");
    *xf = transform_identity();
    *given = m != NULL;
    if (!m) return true;
    jval v = m->val;
    char got[96];
    if (!cJSON_IsArray(v.item))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"transform\" must be an array of operations ({\"translate\": ...}, {\"rotate\": ...}, "
                       "{\"scale\": ...} or {\"matrix\": ...}), got %s",
                       describe(ld, v, got, sizeof got));
    mat4 acc = mat4_identity();
    jiter it = iter_begin(ld, v);
    jval e;
    int r;
    for (size_t i = 0; (r = iter_step(ld, &it, NULL, &e)) > 0; i++) {
        char what[48];
        snprintf(what, sizeof what, "transform[%zu]", i);
        jobj op;
        if (!obj_open(ld, e, what, transform_op_keys, &op)) return false;
        if (op.count != 1)
            return fail_at(ld, offset_of(ld, e.tok),
                           "%s must hold exactly one operation (translate, rotate, scale or matrix), got %zu; put "
                           "each in its own element, they apply in array order",
                           what, op.count);
        const jmember *opm = &op.m[0];
        mat4 step;
        if (strcmp(opm->key, "translate") == 0) {
            vec3 t;
            if (!check_vec3(ld, opm->val, "translate", &NUM_FINITE, &t)) return false;
            step = mat4_translate(t);
        } else if (strcmp(opm->key, "rotate") == 0) {
            char rot_what[96];
            snprintf(rot_what, sizeof rot_what, "\"rotate\" of %s", what);
            if (!read_rotate(ld, opm->val, rot_what, &step)) return false;
        } else if (strcmp(opm->key, "scale") == 0) {
            if (!read_scale(ld, opm->val, &step)) return false;
        } else if (!read_matrix(ld, opm->val, &step)) {
            return false;
        }
        // Each operation acts on the result of the ones before it: M = step * M.
        acc = mat4_mul(&step, &acc);
        if (!mat4_is_affine(&acc))
            return fail_at(ld, offset_of(ld, e.tok), "%s makes the transform overflow single precision", what);
    }
    if (r < 0) return false;
    if (!transform_make(&acc, xf))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"transform\" is singular or too close to it to invert in single precision (determinant "
                       "%g)",
                       mat4_linear_det(&acc));
    return true;
}

// ---------------------------------------------------------------------------------------------
// Objects: add a row to object_types (name, keys, reader) for a new shape.

static const char *const sphere_keys[] = {"type", "center", "radius", "material", "transform", NULL};
static const char *const quad_keys[] = {"type", "q", "u", "v", "material", "transform", NULL};
static const char *const box_keys[] = {"type", "min", "max", "material", "transform", NULL};
static const char *const mesh_keys[] = {"type", "file", "material", "transform", "face_normals", NULL};

// A sphere under a similarity is another sphere; under any other transform, or when its material is
// textured (the texture must turn with it), it becomes an instance.
static bool read_sphere(loader *ld, const jobj *o, const char *what) {
    sphere s = {0};
    transform xf;
    bool moved;
    if (!read_vec3(ld, o, "center", true, &NUM_FINITE, &s.center) ||
        !read_float(ld, o, "radius", true, &NUM_NONZERO_FINITE, &s.radius) ||
        !read_material_ref(ld, o, what, &s.material) || !read_transform(ld, o, &xf, &moved))
        return false;
    if (!moved) return scene_add_sphere(ld->scene, s) || fail_oom(ld);
    double scale;
    const material *m = &ld->scene->materials[s.material];
    bool textured = m->albedo_texture >= 0 || m->emission_texture >= 0;
    if (!textured && mat4_similarity_scale(&xf.m, &scale)) {
        sphere w = s;
        w.center = mat4_apply_point(&xf.m, s.center);
        w.radius = (float)(s.radius * scale);
        if (!v3_is_finite(w.center) || !isfinite(w.radius) || w.radius == 0.0f)
            return fail_at(ld, offset_of_member(ld, o, "transform"),
                           "the transformed sphere is not representable in single precision");
        return scene_add_sphere(ld->scene, w) || fail_oom(ld);
    }
    long i = scene_add_instance_sphere(ld->scene, s);
    if (i < 0) return fail_oom(ld);
    instance in = {INSTANCE_SPHERE, (uint32_t)i, xf, (int32_t)s.material};
    return scene_add_instance(ld->scene, in) || fail_oom(ld);
}

// Adds quads (count of them) under xf if `moved`, pointing at "transform" when the result degenerates.
static bool add_quads(loader *ld, const jobj *o, const quad *q, int count, const transform *xf, bool moved) {
    for (int i = 0; i < count; i++) {
        quad w = q[i];
        if (moved && !quad_transform(&q[i], &xf->m, &w))
            return fail_at(ld, offset_of_member(ld, o, "transform"),
                           "the transformed shape has no area or is not representable in single precision");
        if (!scene_add_quad(ld->scene, w)) return fail_oom(ld);
    }
    return true;
}

static bool read_quad(loader *ld, const jobj *o, const char *what) {
    vec3 q, u, v;
    uint32_t mat;
    transform xf;
    bool moved;
    if (!read_vec3(ld, o, "q", true, &NUM_FINITE, &q) || !read_vec3(ld, o, "u", true, &NUM_FINITE, &u) ||
        !read_vec3(ld, o, "v", true, &NUM_FINITE, &v) || !read_material_ref(ld, o, what, &mat) ||
        !read_transform(ld, o, &xf, &moved))
        return false;
    quad qd;
    if (!quad_make(q, u, v, mat, &qd)) {
        vec3 n = v3_cross(u, v);
        if (v3_is_finite(n) && n.x == 0.0f && n.y == 0.0f && n.z == 0.0f)
            return fail_at(ld, offset_of_member(ld, o, "v"),
                           "\"u\" and \"v\" must be non-zero and not parallel (the quad has no area)");
        return fail_at(ld, offset_of_member(ld, o, "v"), "the quad is too large: its area overflows single precision");
    }
    return add_quads(ld, o, &qd, 1, &xf, moved);
}

static bool read_box(loader *ld, const jobj *o, const char *what) {
    vec3 lo, hi;
    uint32_t mat;
    transform xf;
    bool moved;
    if (!read_vec3(ld, o, "min", true, &NUM_FINITE, &lo) || !read_vec3(ld, o, "max", true, &NUM_FINITE, &hi))
        return false;
    for (int k = 0; k < 3; k++) {
        float a = v3_comp(lo, k), b = v3_comp(hi, k);
        if (!(a < b))
            return fail_at(ld, offset_of_member(ld, o, "max"),
                           "\"max\" must be greater than \"min\" in every coordinate, but \"max\"[%d] = %g <= "
                           "\"min\"[%d] = %g",
                           k, (double)b, k, (double)a);
    }
    if (!read_material_ref(ld, o, what, &mat) || !read_transform(ld, o, &xf, &moved)) return false;
    quad faces[6];
    if (!quad_box(lo, hi, mat, faces))
        return fail_at(ld, offset_of_member(ld, o, "max"), "the box is too large: its faces' areas overflow single "
                                                           "precision");
    return add_quads(ld, o, faces, 6, &xf, moved);
}

// Whether the file name ends in ".obj", in any case.
static bool has_obj_extension(const char *path) {
    size_t n = strlen(path);
    if (n < 4) return false;
    const char *e = path + n - 4;
    return e[0] == '.' && (e[1] | 0x20) == 'o' && (e[2] | 0x20) == 'b' && (e[3] | 0x20) == 'j';
}

// The shared grey Lambertian of faces that have no material of their own.
static bool fallback_material(loader *ld, uint32_t *index) {
    if (ld->fallback_material < 0) {
        material m = material_default(MAT_LAMBERTIAN);
        if ((ld->fallback_material = scene_add_material(ld->scene, &m, NULL)) < 0) return fail_oom(ld);
    }
    *index = (uint32_t)ld->fallback_material;
    return true;
}

/// Turns the material slots of a loaded OBJ into scene materials ("file:name", map_Kd as an image texture)
/// and fills the scene mesh's slot table; *needs_fallback tells whether some faces have no material.
static bool map_obj_materials(loader *ld, jval file, const obj_model *model, scene_mesh *sm, bool *needs_fallback) {
    const char *written = file.item->valuestring;
    size_t where = offset_of(ld, file.tok);
    *needs_fallback = false;
    for (size_t i = 0; i < model->mesh.triangle_count && !*needs_fallback; i++)
        if (model->mesh.triangles[i].material < 0) *needs_fallback = true;
    if (model->material_count && !(sm->slot_material = calloc(model->material_count, sizeof *sm->slot_material)))
        return fail_oom(ld);
    sm->slot_count = model->material_count;
    for (size_t i = 0; i < model->material_count; i++) {
        const obj_material *om = &model->materials[i];
        if (!om->defined) {
            *needs_fallback = true;
            if (!fallback_material(ld, &sm->slot_material[i])) return false;
            continue;
        }
        material m = om->mat;
        m.albedo_texture = m.emission_texture = -1;
        // map_Kd is a diffuse colour: it replaces the albedo of Lambertian materials only (a metal's albedo is Ks).
        if (om->diffuse_map && m.kind == MAT_LAMBERTIAN) {
            // The OBJ reader has resolved the path and warned about (and dropped) missing files.
            struct stat st;
            int e = file_problem(om->diffuse_map, &st);
            char prefix[512];
            snprintf(prefix, sizeof prefix, "mesh file \"%.200s\": material \"%.100s\": ", written, om->name);
            if (e)
                return fail_at(ld, where, "%simage file \"%.300s\": cannot open: %s", prefix, om->diffuse_map,
                               file_problem_text(e));
            uint32_t t;
            if (!load_image(ld, where, prefix, om->diffuse_map, om->diffuse_map, (file_id){st.st_dev, st.st_ino}, &t))
                return false;
            m.albedo_texture = (int32_t)t;
        }
        if (ld->scene->material_count >= LOAD_MAX_ITEMS)
            return fail_at(ld, where, "too many materials (the limit is %d)", LOAD_MAX_ITEMS);
        size_t n = strlen(written) + strlen(om->name) + 2;
        char *name = malloc(n);
        if (!name) return fail_oom(ld);
        snprintf(name, n, "%s:%s", written, om->name);
        long k = scene_add_material(ld->scene, &m, name);
        free(name);
        if (k < 0) return fail_oom(ld);
        sm->slot_material[i] = (uint32_t)k;
    }
    if (*needs_fallback || sm->slot_count == 0) return fallback_material(ld, &sm->default_material);
    sm->default_material = sm->slot_material[0];
    return true;
}

/// Loads an OBJ file into a new scene mesh; *entry records it in the cache.
static bool load_mesh(loader *ld, jval file, const char *path, file_id id, bool face_normals, mesh_entry *entry) {
    obj_model model;
    glint_error err;
    obj_options opt = {collect_warning, ld, false};
    char got[96], note[420];
    if (obj_load(path, &opt, &model, &err) != GLINT_OK)
        return fail_at(ld, offset_of(ld, file.tok), "mesh file %s%s: %s", describe(ld, file, got, sizeof got),
                       resolved_note(file.item->valuestring, path, note, sizeof note), err.message);
    if (ld->warning_oom) {
        obj_model_free(&model);
        return fail_oom(ld);
    }
    scene_mesh sm = {0};
    bool ok = true;
    if (face_normals) {
        // Flat shading: every triangle uses its geometric normal.
        for (size_t i = 0; i < model.mesh.triangle_count; i++)
            model.mesh.triangles[i].n[0] = model.mesh.triangles[i].n[1] = model.mesh.triangles[i].n[2] = -1;
    } else {
        ok = mesh_compute_normals(&model.mesh) || fail_oom(ld);
    }
    ok = ok && map_obj_materials(ld, file, &model, &sm, &entry->needs_fallback);
    // The scene takes the geometry; the model keeps (and frees) its material slots.
    sm.geometry = model.mesh;
    memset(&model.mesh, 0, sizeof model.mesh);
    obj_model_free(&model);
    if (ok && !(sm.path = malloc(strlen(path) + 1))) ok = fail_oom(ld);
    if (!ok) {
        mesh_free(&sm.geometry);
        free(sm.slot_material);
        free(sm.path);
        return false;
    }
    memcpy(sm.path, path, strlen(path) + 1);
    long i = scene_add_mesh(ld->scene, &sm);
    if (i < 0) return fail_oom(ld);
    *entry = (mesh_entry){id, face_normals, entry->needs_fallback, false, (uint32_t)i};
    return true;
}

// A mesh from a file, placed with its own transform; every mesh object is an instance of its file's mesh,
// which is loaded once however often it is placed.
static bool read_mesh(loader *ld, const jobj *o, const char *what) {
    char *path;
    file_id id;
    jval file;
    bool face_normals = false, moved;
    transform xf;
    uint32_t mat = 0;
    const bool override = obj_get(o, "material") != NULL;
    if (!read_file_path(ld, o, "file", "mesh", &path, &id, &file)) return false;
    bool ok = true;
    char got[96], note[420];
    if (!has_obj_extension(path))
        ok = fail_at(
            ld, offset_of(ld, file.tok), "mesh file %s%s: unsupported format; expected a Wavefront OBJ file (.obj)",
            describe(ld, file, got, sizeof got), resolved_note(file.item->valuestring, path, note, sizeof note));
    ok = ok && read_bool(ld, o, "face_normals", &face_normals) && (!override || read_material_ref(ld, o, what, &mat)) &&
         read_transform(ld, o, &xf, &moved);
    mesh_entry *entry = NULL;
    for (size_t i = 0; ok && i < ld->mesh_count && !entry; i++)
        if (ld->meshes[i].id.dev == id.dev && ld->meshes[i].id.ino == id.ino &&
            ld->meshes[i].face_normals == face_normals)
            entry = &ld->meshes[i];
    if (ok && !entry) {
        if (!array_reserve((void **)&ld->meshes, &ld->mesh_cap, ld->mesh_count + 1, sizeof *ld->meshes)) {
            ok = fail_oom(ld);
        } else {
            entry = &ld->meshes[ld->mesh_count];
            ok = load_mesh(ld, file, path, id, face_normals, entry);
            if (ok) ld->mesh_count++;
        }
    }
    free(path);
    if (!ok) return false;
    if (!override && entry->needs_fallback && !entry->warned) {
        entry->warned = true;
        warn_at(ld, offset_of(ld, file.tok),
                "some faces of mesh file %s have no material (no usemtl, or one no material library defines); they "
                "are grey Lambertian unless the object gives a \"material\"",
                describe(ld, file, got, sizeof got));
    }
    instance in = {INSTANCE_MESH, entry->mesh, xf, override ? (int32_t)mat : -1};
    return scene_add_instance(ld->scene, in) || fail_oom(ld);
}

typedef bool (*object_reader)(loader *ld, const jobj *o, const char *what);

static const struct object_type {
    const char *name;
    const char *const *keys;
    object_reader read;
} object_types[] = {
    {"sphere", sphere_keys, read_sphere},
    {"quad", quad_keys, read_quad},
    {"box", box_keys, read_box},
    {"mesh", mesh_keys, read_mesh},
};
#define OBJECT_TYPES (sizeof object_types / sizeof object_types[0])

static bool read_object(loader *ld, jval v, size_t i) {
    char what[64], typed[96];
    size_t t;
    snprintf(what, sizeof what, "object %zu", i);
    if (!open_typed(ld, v, what, object_types, OBJECT_TYPES, sizeof object_types[0], &t)) return false;
    snprintf(typed, sizeof typed, "object %zu (%s)", i, object_types[t].name);
    jobj o;
    return obj_open(ld, v, typed, object_types[t].keys, &o) && object_types[t].read(ld, &o, typed);
}

// ---------------------------------------------------------------------------------------------
// Lights

static const char *const ambient_keys[] = {"type", "intensity", NULL};
static const char *const point_keys[] = {"type", "intensity", "position", NULL};
static const char *const directional_keys[] = {"type", "intensity", "direction", NULL};

static const struct light_type {
    const char *name;
    light_kind kind;
    const char *const *keys;
} light_types[] = {
    {"ambient", LIGHT_AMBIENT, ambient_keys},
    {"point", LIGHT_POINT, point_keys},
    {"directional", LIGHT_DIRECTIONAL, directional_keys},
};
#define LIGHT_TYPES (sizeof light_types / sizeof light_types[0])

static bool read_light(loader *ld, jval v, size_t i) {
    char what[64], typed[96];
    size_t t;
    snprintf(what, sizeof what, "light %zu", i);
    if (!open_typed(ld, v, what, light_types, LIGHT_TYPES, sizeof light_types[0], &t)) return false;
    snprintf(typed, sizeof typed, "light %zu (%s)", i, light_types[t].name);
    jobj o;
    if (!obj_open(ld, v, typed, light_types[t].keys, &o)) return false;
    light l = {0};
    l.kind = light_types[t].kind;
    if (!read_color(ld, &o, "intensity", true, &NUM_NONNEG, &l.intensity)) return false;
    if (l.kind == LIGHT_POINT && !read_vec3(ld, &o, "position", true, &NUM_FINITE, &l.position)) return false;
    if (l.kind == LIGHT_DIRECTIONAL) {
        if (!read_vec3(ld, &o, "direction", true, &NUM_FINITE, &l.direction)) return false;
        if (l.direction.x == 0.0f && l.direction.y == 0.0f && l.direction.z == 0.0f) {
            const jmember *m = obj_get(&o, "direction");
            char got[96];
            return fail_at(ld, offset_of(ld, m->val.tok), "\"direction\" must be a non-zero vector, got %s",
                           describe(ld, m->val, got, sizeof got));
        }
    }
    return scene_add_light(ld->scene, l) || fail_oom(ld);
}

// ---------------------------------------------------------------------------------------------
// Camera

static const char *const viewport_keys[] = {"type", "position", "viewport", "distance", NULL};
static const char *const lookat_keys[] = {"type",          "lookfrom",       "lookat", "vup", "vfov",
                                          "defocus_angle", "focus_distance", NULL};

static const struct camera_type {
    const char *name;
    camera_kind kind;
    const char *const *keys;
} camera_types[] = {
    {"viewport", CAMERA_VIEWPORT, viewport_keys},
    {"lookat", CAMERA_LOOKAT, lookat_keys},
};

static bool read_lookat(loader *ld, const jobj *o, camera *c) {
    if (!read_vec3(ld, o, "lookfrom", false, &NUM_FINITE, &c->lookfrom) ||
        !read_vec3(ld, o, "lookat", false, &NUM_FINITE, &c->lookat) ||
        !read_vec3(ld, o, "vup", false, &NUM_FINITE, &c->vup) ||
        !read_float(ld, o, "vfov", false, &NUM_VFOV, &c->vfov_degrees) ||
        !read_float(ld, o, "defocus_angle", false, &NUM_DEFOCUS, &c->defocus_angle_degrees) ||
        !read_float(ld, o, "focus_distance", false, &NUM_NONNEG, &c->focus_distance))
        return false;
    // The camera basis (camera_prepare, in float) needs a view direction and an up vector not along it.
    vec3 d = v3_sub(c->lookfrom, c->lookat);
    float d2 = v3_len2(d);
    if (!(d2 > 0.0f) || !isfinite(d2))
        return fail_at(ld, offset_of_member(ld, o, obj_get(o, "lookat") ? "lookat" : "lookfrom"),
                       "\"lookfrom\" and \"lookat\" must be different points%s",
                       d2 > 0.0f ? " not so far apart that their distance overflows" : "");
    float up2 = v3_len2(c->vup);
    vec3 side = v3_cross(c->vup, v3_unit(d));
    if (!isfinite(up2) || !(v3_len2(side) > 1e-12f * up2))
        return fail_at(ld, offset_of_member(ld, o, "vup"),
                       "\"vup\" must be a non-zero vector not parallel to the view direction (lookat - lookfrom)");
    return true;
}

static bool read_viewport(loader *ld, const jobj *o, camera *c) {
    const jmember *m = obj_get(o, "position");
    if (m && !check_numbers(ld, m->val, "position", 3, "3 numbers (x, y, z)", &NUM_FINITE_DOUBLE, c->position))
        return false;
    m = obj_get(o, "viewport");
    double size[2];
    if (m) {
        if (!check_numbers(ld, m->val, "viewport", 2, "2 numbers (width, height)", &NUM_POSITIVE_DOUBLE, size))
            return false;
        c->viewport_width = size[0];
        c->viewport_height = size[1];
    }
    return read_double(ld, o, "distance", false, &NUM_POSITIVE_DOUBLE, &c->distance);
}

static bool read_camera(loader *ld, jval v) {
    size_t t;
    if (!open_typed(ld, v, "camera", camera_types, 2, sizeof camera_types[0], &t)) return false;
    char typed[64];
    snprintf(typed, sizeof typed, "camera (%s)", camera_types[t].name);
    jobj o;
    if (!obj_open(ld, v, typed, camera_types[t].keys, &o)) return false;
    camera *c = &ld->scene->camera;
    *c = camera_default();
    c->kind = camera_types[t].kind;
    if (c->kind == CAMERA_VIEWPORT) {
        c->position[0] = c->position[1] = c->position[2] = 0.0;
        c->viewport_width = c->viewport_height = c->distance = 1.0;
        return read_viewport(ld, &o, c);
    }
    return read_lookat(ld, &o, c);
}

// ---------------------------------------------------------------------------------------------
// Render settings

static const char *const render_keys[] = {"width",      "height",     "spp",    "max_depth", "seed",
                                          "integrator", "background", "output", "accel",     NULL};
static const char *const whitted_keys[] = {"type", "mode", NULL};
static const char *const path_keys[] = {"type", NULL};
static const char *const sky_keys[] = {"type", "horizon", "zenith", NULL};
static const char *const constant_keys[] = {"type", "color", NULL};

static const struct integrator_type {
    const char *name;
    integrator_kind kind;
    const char *const *keys;
} integrator_types[] = {
    {"whitted", INTEGRATOR_WHITTED, whitted_keys},
    {"path", INTEGRATOR_PATH, path_keys},
};

static const struct background_type {
    const char *name;
    background_kind kind;
    const char *const *keys;
} background_types[] = {
    {"constant", BACKGROUND_CONSTANT, constant_keys},
    {"sky", BACKGROUND_SKY, sky_keys},
};

static bool read_integrator(loader *ld, jval v, render_settings *rs) {
    char got[96];
    if (cJSON_IsString(v.item)) {
        size_t t = find_name(integrator_types, 2, sizeof integrator_types[0], v.item->valuestring);
        if (t < 2) {
            rs->integrator = integrator_types[t].kind;
            return true;
        }
    }
    if (!cJSON_IsObject(v.item))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"integrator\" must be \"whitted\", \"path\" or an object with a \"type\", got %s",
                       describe(ld, v, got, sizeof got));
    size_t t;
    if (!open_typed(ld, v, "integrator", integrator_types, 2, sizeof integrator_types[0], &t)) return false;
    char typed[64];
    snprintf(typed, sizeof typed, "integrator (%s)", integrator_types[t].name);
    jobj o;
    if (!obj_open(ld, v, typed, integrator_types[t].keys, &o)) return false;
    rs->integrator = integrator_types[t].kind;
    static const char *const modes[] = {"paper", "color"};
    int mode = rs->whitted_mode == WHITTED_PAPER ? 0 : 1;
    if (!read_enum(ld, &o, "mode", modes, 2, &mode)) return false;
    rs->whitted_mode = mode == 0 ? WHITTED_PAPER : WHITTED_COLOR;
    return true;
}

static bool read_background(loader *ld, jval v, render_settings *rs) {
    char got[96];
    if (cJSON_IsNumber(v.item) || cJSON_IsArray(v.item)) {
        rs->background = BACKGROUND_CONSTANT;
        return check_color(ld, v, "background", &NUM_NONNEG, &rs->background_color);
    }
    if (cJSON_IsString(v.item) && strcmp(v.item->valuestring, "sky") == 0) {
        rs->background = BACKGROUND_SKY;
        return true;
    }
    if (!cJSON_IsObject(v.item))
        return fail_at(ld, offset_of(ld, v.tok),
                       "\"background\" must be a colour (a number or [r, g, b]), \"sky\" or an object with a \"type\", "
                       "got %s",
                       describe(ld, v, got, sizeof got));
    size_t t;
    if (!open_typed(ld, v, "background", background_types, 2, sizeof background_types[0], &t)) return false;
    char typed[64];
    snprintf(typed, sizeof typed, "background (%s)", background_types[t].name);
    jobj o;
    if (!obj_open(ld, v, typed, background_types[t].keys, &o)) return false;
    rs->background = background_types[t].kind;
    if (rs->background == BACKGROUND_CONSTANT)
        return read_color(ld, &o, "color", true, &NUM_NONNEG, &rs->background_color);
    return read_color(ld, &o, "horizon", false, &NUM_NONNEG, &rs->sky_horizon) &&
           read_color(ld, &o, "zenith", false, &NUM_NONNEG, &rs->sky_zenith);
}

static bool read_render(loader *ld, jval v) {
    jobj o;
    if (!obj_open(ld, v, "render", render_keys, &o)) return false;
    render_settings *rs = &ld->scene->settings;
    long long width = rs->width, height = rs->height, spp = rs->spp, depth = -1, seed = (long long)rs->seed;
    if (!read_int(ld, &o, "width", false, 1, SCENE_MAX_DIMENSION, &width) ||
        !read_int(ld, &o, "height", false, 1, SCENE_MAX_DIMENSION, &height) ||
        !read_int(ld, &o, "spp", false, 1, SCENE_MAX_SPP, &spp) ||
        !read_int(ld, &o, "max_depth", false, 0, SCENE_MAX_DEPTH, &depth) ||
        !read_int(ld, &o, "seed", false, 0, 9007199254740992LL, &seed))
        return false;
    const jmember *m = obj_get(&o, "integrator");
    if (m && !read_integrator(ld, m->val, rs)) return false;
    m = obj_get(&o, "background");
    if (m && !read_background(ld, m->val, rs)) return false;
    static const char *const transforms[] = {"linear", "gamma2", "srgb"};
    static const output_transform transform_kinds[] = {TRANSFORM_LINEAR, TRANSFORM_GAMMA2, TRANSFORM_SRGB};
    static const char *const accels[] = {"bvh", "bvh2", "none"};
    static const accel_kind accel_kinds[] = {ACCEL_BVH, ACCEL_BVH2, ACCEL_NONE};
    int output = -1, accel = -1;
    if (!read_enum(ld, &o, "output", transforms, 3, &output) || !read_enum(ld, &o, "accel", accels, 3, &accel))
        return false;
    if (output >= 0) rs->transform = transform_kinds[output];
    if (accel >= 0) rs->accel = accel_kinds[accel];
    rs->width = (int)width;
    rs->height = (int)height;
    rs->spp = (int)spp;
    rs->seed = (uint64_t)seed;
    // Without "max_depth" each integrator gets its own default: the paper's 3 bounces, the book's 50.
    if (depth >= 0) rs->max_depth = (int)depth;
    else rs->max_depth = rs->integrator == INTEGRATOR_PATH ? 50 : 3;
    return true;
}

// ---------------------------------------------------------------------------------------------
// The scene

static const char *const scene_keys[] = {"render", "camera", "textures", "materials", "objects", "lights", NULL};

static bool read_scene(loader *ld, jval root) {
    jobj o;
    if (!cJSON_IsObject(root.item)) {
        char got[96];
        return fail_at(ld, offset_of(ld, root.tok), "the scene must be a JSON object, got %s",
                       describe(ld, root, got, sizeof got));
    }
    if (!obj_open(ld, root, "the scene", scene_keys, &o)) return false;
    const jmember *m;
    // Textures before materials before objects, so that each can refer to the one before it whatever the
    // key order in the file.
    if ((m = obj_get(&o, "render")) && !read_render(ld, m->val)) return false;
    if ((m = obj_get(&o, "camera")) && !read_camera(ld, m->val)) return false;
    if ((m = obj_get(&o, "textures")) && !read_named(ld, m->val, "texture", &ld->textures, read_texture)) return false;
    if ((m = obj_get(&o, "materials")) && !read_named(ld, m->val, "material", &ld->materials, read_material))
        return false;
    if ((m = obj_get(&o, "objects")) && !read_array(ld, m->val, "objects", read_object)) return false;
    if ((m = obj_get(&o, "lights")) && !read_array(ld, m->val, "lights", read_light)) return false;
    if (ld->warnings_dropped) {
        char msg[256];
        snprintf(msg, sizeof msg, "%s: warning: %zu more warnings not listed", ld->name, ld->warnings_dropped);
        ld->warnings_dropped = 0;
        if (!scene_add_warning(ld->scene, msg)) ld->warning_oom = true;
    }
    return !ld->warning_oom || fail_oom(ld);
}

glint_status glint_scene_parse(const char *name, const char *text, size_t length, glint_scene **out, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!out) {
        snprintf(err->message, sizeof err->message, "glint_scene_parse: no place to store the scene");
        return GLINT_ERR_INPUT;
    }
    *out = NULL;
    if (!name) name = "<scene>";
    if (!text) length = 0;
    if (length > (size_t)LOAD_MAX_FILE_BYTES) {
        snprintf(err->message, sizeof err->message,
                 "%s: the scene is %zu bytes; at most %d bytes (256 MiB) are allowed", name, length,
                 LOAD_MAX_FILE_BYTES);
        return GLINT_ERR_INPUT;
    }
    if (!text) text = "";
    json_index ix;
    json_scan_error se;
    json_result jr = json_scan(text, length, &ix, &se);
    if (jr != JSON_SCAN_OK) {
        size_t line, col;
        json_line_col(text, length, se.offset, &line, &col);
        if (jr == JSON_SCAN_NOMEM)
            snprintf(err->message, sizeof err->message, "%s: out of memory while reading the scene", name);
        else snprintf(err->message, sizeof err->message, "%s:%zu:%zu: %s", name, line, col, se.message);
        return jr == JSON_SCAN_NOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    // cJSON skips a byte-order mark itself, but handing it the text after one keeps both readers aligned.
    size_t bom = length >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text + bom, length - bom, &end, 0);
    loader ld;
    memset(&ld, 0, sizeof ld);
    ld.name = name;
    ld.text = text;
    ld.len = length;
    ld.ix = &ix;
    ld.err = err;
    ld.status = GLINT_ERR_INPUT;
    ld.fallback_material = -1;
    bool ok = false;
    if (!root) {
        // The scanner accepted the text, so this is cJSON running out of memory (or a cJSON bug).
        size_t line, col;
        json_line_col(text, length, end ? (size_t)(end - text) : 0, &line, &col);
        snprintf(err->message, sizeof err->message,
                 "%s:%zu:%zu: the JSON library could not read the scene here (out of memory?)", name, line, col);
        ld.status = GLINT_ERR_RENDER;
    } else if (ix.count == 0 || !kinds_agree(root, (json_kind)ix.tok[0].kind)) {
        fail_internal(&ld, 0);
    } else if (!(ld.scene = scene_new(name))) {
        fail_oom(&ld);
    } else {
        ok = read_scene(&ld, (jval){root, 0});
    }
    names_free(&ld.materials);
    names_free(&ld.textures);
    free(ld.meshes);
    free(ld.images);
    cJSON_Delete(root);
    json_index_free(&ix);
    if (!ok) {
        glint_scene_free(ld.scene);
        return ld.status;
    }
    *out = ld.scene;
    return GLINT_OK;
}

glint_status glint_scene_load(const char *path, glint_scene **out, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!out) return glint_scene_parse(path, NULL, 0, out, err);
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, strerror(errno));
        return GLINT_ERR_INPUT;
    }
    struct stat st;
    size_t cap = 1 << 16;
    if (fstat(fileno(f), &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            fclose(f);
            snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, strerror(EISDIR));
            return GLINT_ERR_INPUT;
        }
        // A regular file's size is known: read it in one piece (files of other kinds grow the buffer).
        if (S_ISREG(st.st_mode) && st.st_size >= 0 && (unsigned long long)st.st_size <= LOAD_MAX_FILE_BYTES)
            cap = (size_t)st.st_size + 1;
    }
    char *buf = malloc(cap);
    size_t n = 0;
    glint_status status = GLINT_OK;
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n > (size_t)LOAD_MAX_FILE_BYTES) {
            snprintf(err->message, sizeof err->message, "%s: the scene file is larger than %d bytes (256 MiB)", path,
                     LOAD_MAX_FILE_BYTES);
            status = GLINT_ERR_INPUT;
            break;
        }
        if (n < cap) {
            if (ferror(f)) {
                snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno));
                status = GLINT_ERR_INPUT;
            }
            break;
        }
        // Full: grow, up to one byte more than the limit so that a too-large file is noticed.
        size_t bigger = cap * 2 > (size_t)LOAD_MAX_FILE_BYTES + 1 ? (size_t)LOAD_MAX_FILE_BYTES + 1 : cap * 2;
        char *grown = realloc(buf, bigger);
        if (!grown) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = grown;
        cap = bigger;
    }
    fclose(f);
    if (!buf) {
        snprintf(err->message, sizeof err->message, "%s: out of memory while reading the scene file", path);
        return GLINT_ERR_RENDER;
    }
    if (status == GLINT_OK) status = glint_scene_parse(path, buf, n, out, err);
    free(buf);
    return status;
}
