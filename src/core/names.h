// names.h — enums named in files and on the command line: each enum keeps its names in a table beside it, and
// these two look values up in such a table, so that no enum is spelled out twice.
#ifndef GLINT_NAMES_H
#define GLINT_NAMES_H

#include <stddef.h>
#include <string.h>

/// names[v], or "unknown" for a value outside [0, count) (a damaged file's field).
static inline const char *names_get(const char *const *names, size_t count, int v) {
    return v >= 0 && (size_t)v < count ? names[v] : "unknown";
}

/// The index of `name` in names[0, count), or -1.
static inline int names_find(const char *const *names, size_t count, const char *name) {
    for (size_t i = 0; name && i < count; i++)
        if (strcmp(names[i], name) == 0) return (int)i;
    return -1;
}

#endif
