// test_util.h — what the tests that write files share: a temporary directory, paths in it, writing a file.
#ifndef GLINT_TEST_UTIL_H
#define GLINT_TEST_UTIL_H

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char tmpdir[512];

/// Creates the test's directory $TMPDIR/<prefix>-XXXXXX (or under /tmp); false, after perror, when it cannot.
static inline bool tmpdir_make(const char *prefix) {
    const char *base = getenv("TMPDIR");
    snprintf(tmpdir, sizeof tmpdir, "%s/%s-XXXXXX", base && *base ? base : "/tmp", prefix);
    if (mkdtemp(tmpdir)) return true;
    perror("mkdtemp");
    return false;
}

/// `name` in the test's directory; the last 8 results stay valid, so a call may take several paths.
static inline const char *tmp_path(const char *name) {
    static char buf[8][1024];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", tmpdir, name);
    return buf[k];
}

/// Writes n bytes to path; false when the file cannot be opened, written or closed.
static inline bool tmp_write(const char *path, const void *data, size_t n) {
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(data, 1, n, f) == n;
    return fclose(f) == 0 && ok;
}

/// Removes the files in the test's directory (one level) and the directory.
static inline void tmpdir_remove(void) {
    DIR *d = opendir(tmpdir);
    if (!d) return;
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) unlink(tmp_path(e->d_name));
    closedir(d);
    rmdir(tmpdir);
}

#endif
