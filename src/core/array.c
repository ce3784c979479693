// array.c — growing arrays by doubling, with the byte size checked for overflow before every realloc.
#include "core/array.h"

#include <stdint.h>
#include <stdlib.h>

bool array_reserve(void **items, size_t *capacity, size_t needed, size_t item_size) {
    if (needed <= *capacity) return true;
    size_t most = SIZE_MAX / item_size; // the largest element count whose byte size fits in size_t
    if (needed > most) return false;
    size_t cap = *capacity ? *capacity : ARRAY_MIN_CAPACITY;
    // Doubling would overflow only past `most`; stop there, which still holds `needed`.
    while (cap < needed) cap = cap > most / 2 ? most : cap * 2;
    void *grown = realloc(*items, cap * item_size);
    if (!grown) return false;
    *items = grown;
    *capacity = cap;
    return true;
}
