// filepath.c — directory part, absolute test and joining of POSIX paths.
#include "core/filepath.h"

#include <errno.h>
#include <stdio.h>
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

int filepath_problem(const char *path, struct stat *st) {
    if (stat(path, st) != 0) return errno ? errno : ENOENT;
    if (S_ISDIR(st->st_mode)) return EISDIR;
    return S_ISREG(st->st_mode) ? 0 : -1;
}

const char *filepath_problem_text(int problem) { return problem > 0 ? strerror(problem) : "not a regular file"; }

const char *filepath_tail(const char *path, size_t limit, char *buf, size_t size) {
    size_t n = strlen(path);
    if (n <= limit) {
        snprintf(buf, size, "%s", path);
        return buf;
    }
    const char *tail = path + n - limit;
    while (*tail && ((unsigned char)*tail & 0xC0u) == 0x80u) tail++; // not inside a UTF-8 sequence
    snprintf(buf, size, "...%s", tail);
    return buf;
}
