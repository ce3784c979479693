// filepath.c — directory part, absolute test and joining of POSIX paths.
#include "core/filepath.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

FILE *filepath_open_regular(const char *path, struct stat *st, int *problem) {
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer, and no signal could end the wait.
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        *problem = errno ? errno : ENOENT;
        return NULL;
    }
    *problem = fstat(fd, st) != 0 ? errno : S_ISDIR(st->st_mode) ? EISDIR : S_ISREG(st->st_mode) ? 0 : -1;
    int flags = *problem == 0 ? fcntl(fd, F_GETFL) : -1;
    if (*problem == 0 && (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0)) *problem = errno ? errno : EIO;
    FILE *f = *problem == 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        if (*problem == 0) *problem = errno ? errno : ENOMEM;
        close(fd);
    }
    return f;
}

enum { MAX_SYMLINK_HOPS = 40 }; // as the kernel's own limit on a path's links (ELOOP beyond)

char *filepath_final(const char *path, int *error) {
    char *cur = strdup(path);
    for (int hops = 0; cur; hops++) {
        struct stat lsb;
        if (lstat(cur, &lsb) != 0 || !S_ISLNK(lsb.st_mode)) return cur; // not a link: the end of the chain
        if (hops == MAX_SYMLINK_HOPS) {
            free(cur);
            *error = ELOOP;
            return NULL;
        }
        char target[4096];
        ssize_t n = readlink(cur, target, sizeof target - 1);
        if (n < 0) {
            *error = errno;
            free(cur);
            return NULL;
        }
        target[n] = '\0';
        // A relative target is relative to the link's own directory.
        size_t keep = target[0] == '/' ? 0 : filepath_dir_length(cur);
        char *next = malloc(keep + (size_t)n + 1);
        if (next) snprintf(next, keep + (size_t)n + 1, "%.*s%s", (int)keep, cur, target);
        free(cur);
        cur = next;
    }
    *error = ENOMEM;
    return NULL;
}

// The directory of `path` (".": none given) by device and inode, and where its last component starts.
static bool directory_of(const char *path, struct stat *dir, const char **base) {
    size_t n = filepath_dir_length(path);
    *base = path + n;
    if (n == 0) return stat(".", dir) == 0;
    char *d = malloc(n + 1);
    if (!d) return false;
    memcpy(d, path, n);
    d[n] = '\0';
    bool ok = stat(d, dir) == 0;
    free(d);
    return ok;
}

bool filepath_same_target(const char *a, const char *b) {
    if (strcmp(a, b) == 0) return true;
    int e = 0;
    char *fa = filepath_final(a, &e), *fb = filepath_final(b, &e);
    bool same = false;
    struct stat sa, sb;
    if (fa && fb) {
        bool ea = stat(fa, &sa) == 0, eb = stat(fb, &sb) == 0;
        if (ea && eb) {
            same = sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
        } else if (!ea && !eb) {
            // Names to be created: the same when their directories are one and their last names equal.
            const char *ba, *bb;
            same = directory_of(fa, &sa, &ba) && directory_of(fb, &sb, &bb) && sa.st_dev == sb.st_dev &&
                   sa.st_ino == sb.st_ino && strcmp(ba, bb) == 0;
        }
    }
    free(fa);
    free(fb);
    return same;
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
