// strmap.h — a string -> number hash map (FNV-1a, open addressing with linear probing) over keys the
// caller owns: the map stores each key's pointer and length, never a copy, so keys must outlive it.
//
// Usage: a zeroed strmap is empty; strmap_put adds or replaces, strmap_get looks up, strmap_free releases.
// Keys are byte strings (pointer + length), so a key need not be NUL-terminated.
#ifndef GLINT_STRMAP_H
#define GLINT_STRMAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// One slot of the table; empty while key is NULL.
typedef struct strmap_slot {
    const char *key; ///< not owned
    size_t len;
    size_t value;
} strmap_slot;

/// The map. Invariant: capacity is 0 or a power of two, and count <= capacity / 2 (probes stay short).
typedef struct strmap {
    strmap_slot *slots;
    size_t capacity, count;
} strmap;

/// The 64-bit FNV-1a hash of the n bytes at s.
uint64_t strmap_hash(const char *s, size_t n);
/// Whether key[0, len) is in the map; when it is and value is not NULL, *value is what it maps to.
bool strmap_get(const strmap *m, const char *key, size_t len, size_t *value);
/// Maps key[0, len) to value (replacing an earlier value); the map keeps the pointer. False when out of memory.
bool strmap_put(strmap *m, const char *key, size_t len, size_t value);
/// Frees the table and leaves an empty map.
void strmap_free(strmap *m);

#endif
