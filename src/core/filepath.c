// filepath.c — directory part, absolute test and joining of POSIX paths.
#include "core/filepath.h"

#include <stdlib.h>
#include <string.h>

size_t filepath_dir_length(const char *path) {
    const char *slash = strrchr(path, '/');
    return slash ? (size_t)(slash - path) + 1 : 0;
}

bool filepath_is_absolute(const char *path, size_t len) { return len > 0 && path[0] == '/'; }

char *filepath_join(const char *dir, size_t dir_len, const char *rel, size_t rel_len) {
    size_t d = filepath_is_absolute(rel, rel_len) ? 0 : dir_len;
    char *p = malloc(d + rel_len + 1);
    if (!p) return NULL;
    memcpy(p, dir, d);
    memcpy(p + d, rel, rel_len);
    p[d + rel_len] = '\0';
    return p;
}
