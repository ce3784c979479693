// test_load.h — a scene file loaded for a test, with the command line's overrides applied (glint_overrides).
#ifndef GLINT_TEST_LOAD_H
#define GLINT_TEST_LOAD_H

#include "glint.h"

#include <stdio.h>

/// The scene file at `path` with the overrides *o (NULL: none); NULL, the message printed, when either fails.
static inline glint_scene *test_load(const char *path, const glint_overrides *o) {
    glint_scene *s = NULL;
    glint_error err;
    if (glint_scene_load(path, &s, &err) != GLINT_OK || (o && glint_scene_override(s, o, &err) != GLINT_OK)) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        glint_scene_free(s);
        return NULL;
    }
    return s;
}

/// The path of tests/data/`name` in the source tree (valid until the next call).
static inline const char *test_data_path(const char *name) {
    static char path[4096];
    snprintf(path, sizeof path, "%s/tests/data/%s", GLINT_SOURCE_DIR, name);
    return path;
}

#endif
