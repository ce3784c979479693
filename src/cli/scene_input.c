// scene_input.c — the scene a program renders, from a file or standard input, and the check that the output
// does not replace it.
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

// Reads standard input as a scene: at most GLINT_MAX_SCENE_BYTES + 1 bytes, one more than a scene may have,
// so that a larger input (even an endless one) is refused without reading or holding the rest. NULL on
// failure, with the message in *err and the status in *st (GLINT_ERR_RENDER when memory runs out).
char *cli_read_stdin(size_t *length, glint_status *st, glint_error *err) {
    const size_t most = GLINT_MAX_SCENE_BYTES + 1;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, stdin);
        if (n < cap || cap == most) break;
        size_t bigger = cap > most / 2 ? most : cap * 2;
        char *grown = realloc(buf, bigger);
        if (!grown) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = grown;
        cap = bigger;
    }
    *st = GLINT_ERR_INPUT;
    if (!buf || (ferror(stdin) && errno == ENOMEM)) {
        snprintf(err->message, sizeof err->message, "standard input: out of memory while reading the scene");
        *st = GLINT_ERR_RENDER;
    } else if (ferror(stdin)) {
        snprintf(err->message, sizeof err->message, "standard input: cannot read the scene");
    } else if (n > GLINT_MAX_SCENE_BYTES) {
        snprintf(err->message, sizeof err->message, "standard input: the scene is larger than %zu bytes (%zu MiB)",
                 GLINT_MAX_SCENE_BYTES, GLINT_MAX_SCENE_BYTES >> 20);
    } else {
        *length = n;
        return buf;
    }
    free(buf);
    return NULL;
}

glint_status cli_load_scene(const char *path, int threads, glint_scene **scene, glint_error *err) {
    glint_load_options opt = {.threads = threads};
    if (strcmp(path, "-") != 0) return glint_scene_load_with(path, &opt, scene, err);
    size_t length = 0;
    glint_status st;
    char *text = cli_read_stdin(&length, &st, err);
    if (!text) return st;
    st = glint_scene_parse_with("<stdin>", text, length, &opt, scene, err);
    free(text);
    return st;
}

// Whether the output would replace the scene file (the same file by device and inode, whatever the names and
// links: `glint a.png -o ./a.png`, or a scene on standard input redirected from the output).
bool cli_output_is_scene(const char *output, const char *scene_path) {
    struct stat out, in;
    if (strcmp(output, "-") == 0 || stat(output, &out) != 0) return false;
    int found = strcmp(scene_path, "-") == 0 ? fstat(STDIN_FILENO, &in) : stat(scene_path, &in);
    return found == 0 && S_ISREG(in.st_mode) && in.st_dev == out.st_dev && in.st_ino == out.st_ino;
}
