// fuzz_map.h — the body of the map readers' libFuzzer targets (fuzz_exr.c, fuzz_hdr.c): any bytes must give a
// map of finite, non-negative values within the size limit, or a message naming the file; never a crash, a
// hang, a leak or undefined behaviour.
#ifndef GLINT_FUZZ_MAP_H
#define GLINT_FUZZ_MAP_H

#include "fuzz_file.h"
#include "io/map_read.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

static int fuzz_map(const uint8_t *data, size_t size, map_kind kind) {
    image_rgb img;
    glint_error err;
    const char *path = fuzz_file(data, size, "map");
    if (map_read(path, kind, &img, &err) == GLINT_OK) {
        if (img.width <= 0 || img.height <= 0 || !img.pixels ||
            (size_t)img.width * (size_t)img.height > MAP_READ_MAX_PIXELS)
            __builtin_trap();
        size_t n = (size_t)img.width * (size_t)img.height * 3;
        for (size_t i = 0; i < n; i++)
            if (!(img.pixels[i] >= 0.0f && isfinite(img.pixels[i]))) __builtin_trap();
        image_rgb_free(&img);
    } else if (img.pixels || memchr(err.message, '\0', sizeof err.message) == NULL ||
               strncmp(err.message, path, strlen(path)) != 0) {
        __builtin_trap(); // every refusal names the file
    }
    return 0;
}

#endif
