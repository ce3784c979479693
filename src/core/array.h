// array.h — the one growth policy of glint's growable arrays: capacities double, overflow is checked.
//
// Usage: keep a pointer, a count and a capacity side by side, and reserve room before each append:
//     if (!array_reserve((void **)&items, &capacity, count + 1, sizeof *items)) return out_of_memory();
//     items[count++] = item;
// Doubling makes n appends cost O(n) element copies in all; the first allocation holds ARRAY_MIN_CAPACITY.
#ifndef GLINT_ARRAY_H
#define GLINT_ARRAY_H

#include <stdbool.h>
#include <stddef.h>

/// Elements of the first allocation: small arrays do not reallocate for their first few appends.
#define ARRAY_MIN_CAPACITY 16

/// Makes *items (room for *capacity elements of item_size > 0 bytes) hold at least `needed` elements: the
/// capacity doubles from ARRAY_MIN_CAPACITY until it suffices. False (the array untouched) when the size
/// in bytes would overflow or memory runs out; existing elements are kept either way.
bool array_reserve(void **items, size_t *capacity, size_t needed, size_t item_size);

#endif
