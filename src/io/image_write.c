// image_write.c — PNG, PPM and PFM output, written to a temporary file and renamed into place.
#include "render/film.h"

#include <stdio.h>

glint_status glint_image_write(const glint_image *img, const char *path, glint_format format, glint_error *err) {
    (void)img; (void)format;
    snprintf(err->message, sizeof err->message, "%s: image writing is not written yet", path);
    return GLINT_ERR_RENDER;
}
