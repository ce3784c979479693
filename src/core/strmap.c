// strmap.c — the string map: FNV-1a hashing, linear probing, a table kept at most half full.
#include "core/strmap.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { STRMAP_MIN_CAPACITY = 16 };

uint64_t strmap_hash(const char *s, size_t n) {
    uint64_t h = UINT64_C(14695981039346656037); // FNV-1a offset basis and prime (64-bit)
    for (size_t i = 0; i < n; i++) h = (h ^ (unsigned char)s[i]) * UINT64_C(1099511628211);
    return h;
}

// The slot holding key, or the empty slot where it would go; the table must have a free slot.
static strmap_slot *find_slot(const strmap *m, const char *key, size_t len) {
    size_t mask = m->capacity - 1;
    for (size_t i = (size_t)strmap_hash(key, len) & mask;; i = (i + 1) & mask) {
        strmap_slot *s = &m->slots[i];
        if (!s->key || (s->len == len && memcmp(s->key, key, len) == 0)) return s;
    }
}

bool strmap_get(const strmap *m, const char *key, size_t len, size_t *value) {
    if (!m->capacity) return false;
    const strmap_slot *s = find_slot(m, key, len);
    if (!s->key) return false;
    if (value) *value = s->value;
    return true;
}

// Rehashes into twice the room (at least STRMAP_MIN_CAPACITY slots).
static bool grow(strmap *m) {
    size_t capacity = m->capacity ? m->capacity * 2 : STRMAP_MIN_CAPACITY;
    if (capacity > SIZE_MAX / sizeof(strmap_slot)) return false;
    strmap bigger = {calloc(capacity, sizeof(strmap_slot)), capacity, m->count};
    if (!bigger.slots) return false;
    for (size_t i = 0; i < m->capacity; i++)
        if (m->slots[i].key) *find_slot(&bigger, m->slots[i].key, m->slots[i].len) = m->slots[i];
    free(m->slots);
    *m = bigger;
    return true;
}

bool strmap_put(strmap *m, const char *key, size_t len, size_t value) {
    // Keeping the table at most half full bounds the expected probe length.
    if ((m->count + 1) * 2 > m->capacity && !grow(m)) return false;
    strmap_slot *s = find_slot(m, key, len);
    if (!s->key) m->count++;
    *s = (strmap_slot){key, len, value};
    return true;
}

void strmap_free(strmap *m) {
    free(m->slots);
    memset(m, 0, sizeof *m);
}
