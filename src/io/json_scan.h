// json_scan.h — a strict JSON syntax checker that also records where every value and key starts.
// The scene loader lets cJSON build the tree, and uses this index to put file:line:col on every error.
#ifndef GLINT_JSON_SCAN_H
#define GLINT_JSON_SCAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// Limits that keep a hostile file from using unbounded time, stack or memory.
enum {
    JSON_MAX_DEPTH = 128,          ///< nested arrays/objects; scenes need fewer than 10
    JSON_MAX_VALUES = 1 << 25,     ///< values plus keys: about 2.5 million spheres
    JSON_MAX_NUMBER_LENGTH = 63,   ///< longest number text cJSON reads correctly
};

/// What a token is; keys are JSON_STRING tokens that precede their value.
typedef enum json_kind {
    JSON_OBJECT, JSON_ARRAY, JSON_STRING, JSON_NUMBER, JSON_TRUE, JSON_FALSE, JSON_NULL
} json_kind;

/// One value or key, in document (pre-)order: the same order as cJSON's tree.
typedef struct json_token {
    uint32_t offset; ///< byte offset of its first character (the opening quote of a string)
    uint32_t next;   ///< index of the first token after this one and everything nested in it
    uint8_t kind;    ///< a json_kind
} json_token;

/// Every token of a document.
typedef struct json_index {
    json_token *tok;
    size_t count, capacity;
} json_index;

/// Outcome of json_scan.
typedef enum json_result { JSON_SCAN_OK, JSON_SCAN_SYNTAX, JSON_SCAN_NOMEM } json_result;

/// Where and why a scan failed; the message has no position (the caller adds "file:line:col: ").
typedef struct json_scan_error {
    size_t offset;
    char message[512];
} json_scan_error;

/// Checks that text[0, len) is exactly one RFC 8259 JSON value (an optional UTF-8 byte-order mark and
/// surrounding whitespace allowed) within the limits above, and fills *ix. On failure *ix is empty.
json_result json_scan(const char *text, size_t len, json_index *ix, json_scan_error *e);
/// Frees the tokens of *ix and empties it.
void json_index_free(json_index *ix);
/// 1-based line and column (counted in UTF-8 characters) of byte `offset` of text.
void json_line_col(const char *text, size_t len, size_t offset, size_t *line, size_t *col);

#endif
