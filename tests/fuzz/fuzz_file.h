// fuzz_file.h — the fuzz input as a file, for readers that take a path (checkpoints, merge parts, maps): one
// temporary file a process, rewritten for every input and removed at exit.
#ifndef GLINT_FUZZ_FILE_H
#define GLINT_FUZZ_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char fuzz_dir[64];
static char fuzz_path_buf[128];

static void fuzz_cleanup(void) {
    char cmd[96];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", fuzz_dir);
    if (fuzz_dir[0] && system(cmd) != 0) fprintf(stderr, "cannot remove %s\n", fuzz_dir);
}

/// The path of a file named `name` in the process's temporary directory (made on first use).
static const char *fuzz_path(const char *name) {
    if (!fuzz_dir[0]) {
        snprintf(fuzz_dir, sizeof fuzz_dir, "/tmp/glint-fuzz-XXXXXX");
        if (!mkdtemp(fuzz_dir)) abort();
        atexit(fuzz_cleanup);
    }
    snprintf(fuzz_path_buf, sizeof fuzz_path_buf, "%s/%s", fuzz_dir, name);
    return fuzz_path_buf;
}

/// Writes the input to the file `name` of the temporary directory and returns its path.
static const char *fuzz_file(const uint8_t *data, size_t size, const char *name) {
    const char *path = fuzz_path(name);
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) abort();
    return path;
}

#endif
