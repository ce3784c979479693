// json_read.h — typed reading of a JSON document with a position on every message: numbers in ranges,
// vectors, colours, flags, enumerations and objects with a fixed set of keys, each rejected value named
// as "file:line:col: what is wrong, what was expected". Knows JSON, not what the document describes.
//
// json_scan checks the syntax and records where every value starts; cJSON builds the tree and unescapes
// strings. Both list values in document order, so the reader walks the cJSON tree and the token index
// side by side (jr_val = node + token) and can point at any value it rejects.
//
// Usage: fill a json_reader (name, text, index, err), take the root with jr_root, open objects with
// jr_open (or jr_open_typed for objects with a "type"), read members with jr_read_*. Every function that
// returns false has written the message to rd->err and set rd->status.
#ifndef GLINT_JSON_READ_H
#define GLINT_JSON_READ_H

#include "core/status.h"
#include "core/vec.h"
#include "io/json_scan.h"

#include <cjson/cJSON.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__)
#define JR_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define JR_PRINTF(fmt, args)
#endif

/// Keys a typed object may have (every key list of the scene format is shorter).
#define JR_MAX_KEYS 16

/// The document being read and where messages go; readers of a format embed it in their own state.
typedef struct json_reader {
    const char *name;      ///< file name for messages
    const char *text;      ///< the document, len bytes
    size_t len;
    const json_index *ix;  ///< json_scan's token index of text
    glint_error *err;      ///< receives the message of the first failure
    glint_status status;   ///< what a failure returns: GLINT_ERR_INPUT (set by jr_fail_at) unless a caller says otherwise
    /// The document is one value a program passed to a call (the scene API), not a file: messages open with
    /// "name: " (the call's name), as no line or column would mean anything to the caller.
    bool call;
} json_reader;

/// A value: its cJSON node and its token in the position index.
typedef struct jr_val {
    const cJSON *item;
    uint32_t tok;
} jr_val;

/// Walks the members of an object or the elements of an array, in step with the token index.
typedef struct jr_iter {
    const cJSON *item;
    uint32_t tok, end;
    bool object;
} jr_iter;

/// A key the object may have, found in the file.
typedef struct jr_member {
    const char *key; ///< unescaped
    uint32_t key_tok;
    jr_val val;
} jr_member;

/// An object whose keys were all checked against a list: no unknown and no repeated key.
typedef struct jr_obj {
    jr_val self;
    const char *what; ///< "render", "object 3 (sphere)", ... for messages
    size_t count;
    jr_member m[JR_MAX_KEYS];
} jr_obj;

/// The numbers a parameter accepts; desc says so in messages ("a number in [0, 1]").
typedef struct jr_numspec {
    double lo, hi;
    unsigned flags; ///< JR_LO_OPEN, ...
    const char *desc;
} jr_numspec;

/// Flags of a jr_numspec.
enum {
    JR_LO_OPEN = 1u,     ///< lo itself is excluded
    JR_HI_OPEN = 2u,     ///< hi itself is excluded
    JR_NONZERO = 4u,     ///< zero is excluded
    JR_FLOAT = 8u,       ///< stored as float: checks apply to the value after rounding to float
    JR_FLOAT_RANGE = 16u ///< kept in double, but within float range (it is converted at some point)
};

/// Any finite float.
extern const jr_numspec JR_FINITE;
/// A float in [0, 1].
extern const jr_numspec JR_UNIT;
/// A finite float >= 0.
extern const jr_numspec JR_NONNEG;
/// A finite float > 0.
extern const jr_numspec JR_POSITIVE;
/// A finite non-zero float.
extern const jr_numspec JR_NONZERO_FINITE;
/// A finite double within float range.
extern const jr_numspec JR_FINITE_DOUBLE;
/// A double > 0 within float range.
extern const jr_numspec JR_POSITIVE_DOUBLE;

/// Byte offset of token tok.
size_t jr_offset(const json_reader *rd, uint32_t tok);
/// Writes "name:line:col: <label><message>" for the byte at `offset` into buf (label is "" or "warning: ").
JR_PRINTF(6, 0) void jr_vformat(const json_reader *rd, char *buf, size_t size, size_t offset, const char *label,
                                const char *fmt, va_list ap);
/// Writes "name:line:col: message" into r->err and sets r->status; returns false so callers can `return jr_fail_at(...)`.
JR_PRINTF(3, 4) bool jr_fail_at(json_reader *rd, size_t offset, const char *fmt, ...);
/// Reports that the token index and cJSON's tree disagree at token tok (a bug, not a user error); false.
bool jr_fail_internal(json_reader *rd, uint32_t tok);
/// The document's root value; false (message written) when the index and the tree disagree about it.
bool jr_root(json_reader *rd, const cJSON *root, jr_val *out);

/// The shortest decimal that reads back as x, as a person writes JSON (0.5, 1e39; 1e999 for infinity, "NaN"
/// quoted, as no JSON number is one).
void jr_number_text(double x, char *buf, size_t size);
/// The value as the file spells it, for "got ..." clauses: "abc", 1e999, [1, 2], or "an object".
const char *jr_describe(const json_reader *rd, jr_val v, char *buf, size_t size);
/// Bytes of a long file name that messages show: its end, after "...".
#define JR_PATH_SHOWN 60
/// A string naming a file as the file spells it, with its quotes; a long one keeps its last JR_PATH_SHOWN
/// bytes (the file name and its nearest directories), after "...". Other values as jr_describe.
const char *jr_describe_path(const json_reader *rd, jr_val v, char *buf, size_t size);
/// A key as the file spells it, with its quotes, cut after 40 bytes.
const char *jr_key_source(const json_reader *rd, uint32_t key_tok, char *buf, size_t size);

/// An iterator over the members of an object or the elements of an array.
jr_iter jr_iter_begin(const json_reader *rd, jr_val container);
/// 1 with the next value (and for objects its key token), 0 at the end, -1 (message written) on disagreement.
int jr_iter_next(json_reader *rd, jr_iter *it, uint32_t *key_tok, jr_val *val);

/// Checks v is an object whose keys all belong to `keys` (NULL-terminated), each at most once; fills *o.
bool jr_open(json_reader *rd, jr_val v, const char *what, const char *const *keys, jr_obj *o);
/// The member `key` of o, or NULL.
const jr_member *jr_get(const jr_obj *o, const char *key);
/// The offset to blame for a problem with `key`: the key's value if given, else the whole object.
size_t jr_member_offset(const json_reader *rd, const jr_obj *o, const char *key);
/// The member `key` of o into *m (NULL when absent); false (message written) when absent but required.
bool jr_lookup(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_member **m);
/// Index of `s` in a table whose entries begin with their name (a const char *), or `count`.
size_t jr_find_name(const void *table, size_t count, size_t stride, const char *s);
/// Reads the required "type" of object v, one of the names of `table`; `what` names v in messages.
bool jr_open_typed(json_reader *rd, jr_val v, const char *what, const void *table, size_t count, size_t stride,
                   size_t *type);

/// A number as `sp` says; key and index (-1: none) name it in messages.
bool jr_check_number(json_reader *rd, jr_val v, const char *key, int index, const jr_numspec *sp, double *out);
/// Exactly n numbers in an array; `shape` completes "must be an array of ...", e.g. "3 numbers (x, y, z)".
bool jr_check_numbers(json_reader *rd, jr_val v, const char *key, size_t n, const char *shape, const jr_numspec *sp,
                      double *out);
/// [x, y, z], every component as `sp` says.
bool jr_check_vec3(json_reader *rd, jr_val v, const char *key, const jr_numspec *sp, vec3 *out);
/// A colour: one number (grey) or [r, g, b], every component as `sp` says.
bool jr_check_color(json_reader *rd, jr_val v, const char *key, const jr_numspec *sp, vec3 *out);

// The member readers: an absent optional key leaves *out as it is (the default); an absent required key
// is an error naming the object.

/// A float member.
bool jr_read_float(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp,
                   float *out);
/// A double member.
bool jr_read_double(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp,
                    double *out);
/// An integer member in [lo, hi] (both exact in double).
bool jr_read_int(json_reader *rd, const jr_obj *o, const char *key, bool required, long long lo, long long hi,
                 long long *out);
/// A vector member [x, y, z].
bool jr_read_vec3(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp, vec3 *out);
/// A colour member: a number or [r, g, b].
bool jr_read_color(json_reader *rd, const jr_obj *o, const char *key, bool required, const jr_numspec *sp,
                   vec3 *out);
/// An optional true/false member.
bool jr_read_bool(json_reader *rd, const jr_obj *o, const char *key, bool *out);
/// An optional member that is one of the strings `names` (count of them); *out is its index.
bool jr_read_enum(json_reader *rd, const jr_obj *o, const char *key, const char *const *names, size_t count,
                  int *out);

#endif
