// hdr_read.c — Radiance .hdr files through stb_image: the signature and the declared size are checked
// before anything is decoded, so that a hostile header cannot make it allocate gigabytes.
#include "io/hdr_read.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

bool hdr_read_is_radiance(const unsigned char *head, size_t size) {
    return (size >= 10 && memcmp(head, "#?RADIANCE", 10) == 0) || (size >= 6 && memcmp(head, "#?RGBE", 6) == 0);
}

glint_status hdr_read(const char *path, image_rgb *out, glint_error *err) {
    out->width = out->height = 0;
    out->pixels = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, strerror(errno));
        return errno == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    char magic[10] = {0};
    size_t got = fread(magic, 1, sizeof magic, f);
    if (!hdr_read_is_radiance((const unsigned char *)magic, got)) {
        fclose(f);
        snprintf(err->message, sizeof err->message,
                 "%s: not a Radiance .hdr image (expected a file starting with \"#?RADIANCE\" or \"#?RGBE\")", path);
        return GLINT_ERR_INPUT;
    }
    rewind(f);
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_file(f, &w, &h, &channels) || w <= 0 || h <= 0) {
        fclose(f);
        snprintf(err->message, sizeof err->message, "%s: unreadable .hdr header: %s", path, stbi_failure_reason());
        return GLINT_ERR_INPUT;
    }
    if ((size_t)w * (size_t)h > HDR_READ_MAX_PIXELS) {
        fclose(f);
        snprintf(err->message, sizeof err->message, "%s: the image is %dx%d pixels; at most %zu pixels are allowed",
                 path, w, h, (size_t)HDR_READ_MAX_PIXELS);
        return GLINT_ERR_INPUT;
    }
    rewind(f);
    float *pixels = stbi_loadf_from_file(f, &w, &h, &channels, 3);
    fclose(f);
    if (!pixels) {
        const char *why = stbi_failure_reason();
        bool oom = why && strstr(why, "outofmem") != NULL;
        snprintf(err->message, sizeof err->message, "%s: %s: %s", path, oom ? "out of memory" : "corrupt .hdr image",
                 why ? why : "unknown error");
        return oom ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    // Radiance values are linear already; a non-finite or negative one would poison every sample that sees it.
    size_t n = (size_t)w * (size_t)h * 3u;
    for (size_t i = 0; i < n; i++)
        if (!(pixels[i] >= 0.0f) || pixels[i] > 3.4e38f) pixels[i] = 0.0f;
    // stb allocates with malloc, so the pixels are freed as every image_rgb is.
    out->width = w;
    out->height = h;
    out->pixels = pixels;
    return GLINT_OK;
}
