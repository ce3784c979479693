// map_read.c — one open and one look at the first bytes for every HDR map, then the format's reader.
#include "io/map_read.h"
#include "core/filepath.h"
#include "io/exr_read.h"
#include "io/hdr_read.h"

#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>

glint_status map_read(const char *path, map_kind kind, image_rgb *out, glint_error *err) {
    *out = (image_rgb){0};
    struct stat st;
    int problem = 0;
    FILE *f = filepath_open_regular(path, &st, &problem);
    if (!f) {
        snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, filepath_problem_text(problem));
        return problem == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    unsigned char head[16] = {0};
    size_t got = fread(head, 1, sizeof head, f);
    rewind(f);
    glint_status status;
    if (exr_read_is_exr(head, got) && kind != MAP_HDR) {
        status = exr_read_open(f, path, out, err);
    } else if (hdr_read_is_radiance(head, got) && kind != MAP_EXR) {
        status = hdr_read_open(f, path, out, err);
    } else {
        snprintf(err->message, sizeof err->message, "%s: not %s image (expected a file starting with %s)", path,
                 kind == MAP_EXR ? "an OpenEXR" : kind == MAP_HDR ? "a Radiance .hdr" : "an OpenEXR or Radiance .hdr",
                 kind == MAP_EXR ? "the bytes 76 2f 31 01" : kind == MAP_HDR ? "\"#?RADIANCE\" or \"#?RGBE\""
                 : "the bytes 76 2f 31 01, \"#?RADIANCE\" or \"#?RGBE\"");
        status = GLINT_ERR_INPUT;
    }
    fclose(f);
    return status;
}
