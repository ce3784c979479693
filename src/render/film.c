// film.c — the rendered image and its conversion to 8-bit display values.
#include "render/film.h"

#include <math.h>
#include <stdlib.h>

glint_image *film_new(int width, int height, output_transform encoding) {
    glint_image *img = malloc(sizeof *img);
    if (!img) return NULL;
    img->width = width;
    img->height = height;
    img->transform = encoding;
    img->rgb = calloc((size_t)width * (size_t)height * 3u, sizeof(float));
    if (!img->rgb) { free(img); return NULL; }
    return img;
}

uint8_t film_encode(float v, output_transform encoding) {
    if (!(v > 0.0f)) return 0; // also maps NaN to black
    switch (encoding) {
    case TRANSFORM_LINEAR: break;
    case TRANSFORM_GAMMA2: v = sqrtf(v); break;
    case TRANSFORM_SRGB: v = v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f; break;
    }
    if (v >= 1.0f) return 255;
    return (uint8_t)lrintf(v * 255.0f);
}

void glint_image_info(const glint_image *img, int *width, int *height, const float **rgb) {
    *width = img->width;
    *height = img->height;
    *rgb = img->rgb;
}

uint8_t glint_image_byte(const glint_image *img, int x, int y, int c) {
    return film_encode(img->rgb[((size_t)y * (size_t)img->width + (size_t)x) * 3u + (size_t)c], img->transform);
}

void glint_image_free(glint_image *img) {
    if (!img) return;
    free(img->rgb);
    free(img);
}
