// film.c — the rendered image, the running sums behind it, and the conversion of linear values to 8 bits.
#include "film/film.h"

#include <math.h>
#include <stdlib.h>

glint_image *film_image_new(int width, int height, output_transform encoding) {
    glint_image *img = malloc(sizeof *img);
    if (!img) return NULL;
    img->width = width;
    img->height = height;
    img->transform = encoding;
    img->x0 = img->y0 = 0;
    img->full_width = width;
    img->full_height = height;
    img->rgb = calloc((size_t)width * (size_t)height * 3u, sizeof(float));
    if (!img->rgb) {
        free(img);
        return NULL;
    }
    return img;
}

bool film_image_is_region(const glint_image *img) {
    return img->x0 != 0 || img->y0 != 0 || img->width != img->full_width || img->height != img->full_height;
}

void film_image_free(glint_image *img) {
    if (!img) return;
    free(img->rgb);
    free(img);
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

float film_decode(uint8_t byte, output_transform encoding) {
    double v = byte / 255.0, x = v;
    if (encoding == TRANSFORM_GAMMA2) x = v * v;
    else if (encoding == TRANSFORM_SRGB) x = v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
    // The inverse lands next to the value that encodes back; a few float steps settle it exactly.
    float f = (float)x;
    for (int i = 0; i < 64 && film_encode(f, encoding) < byte; i++) f = nextafterf(f, 2.0f);
    for (int i = 0; i < 64 && film_encode(f, encoding) > byte; i++) f = nextafterf(f, -1.0f);
    return f;
}

bool film_init(film *f, const int region[4], int full_width, int full_height, int spp, int passes,
               output_transform encoding) {
    int width = region[2] - region[0], height = region[3] - region[1];
    f->spp = spp;
    f->sums = NULL;
    f->keep_all_sums = false;
    f->x0 = region[0];
    f->y0 = region[1];
    f->image = film_image_new(width, height, encoding);
    if (!f->image) return false;
    f->image->x0 = region[0];
    f->image->y0 = region[1];
    f->image->full_width = full_width;
    f->image->full_height = full_height;
    if (passes > 1) {
        f->sums = malloc((size_t)width * (size_t)height * 3u * sizeof *f->sums);
        if (!f->sums) {
            film_release(f);
            return false;
        }
    }
    return true;
}

bool film_keep_all_sums(film *f) {
    f->keep_all_sums = true;
    size_t n = (size_t)f->image->width * (size_t)f->image->height * 3u;
    // Zeroed: a checkpoint written before every pixel had a pass holds defined bytes for them.
    if (f->sums) memset(f->sums, 0, n * sizeof *f->sums);
    else f->sums = calloc(n, sizeof *f->sums);
    return f->sums != NULL;
}

void film_restore_means(film *f, const uint32_t *counts) {
    size_t n = (size_t)f->image->width * (size_t)f->image->height;
    for (size_t i = 0; i < n; i++)
        if (counts[i] > 0) film_store_mean(f, i, &f->sums[i * 3u], (int)counts[i]);
}

glint_image *film_take_image(film *f) {
    glint_image *img = f->image;
    f->image = NULL;
    return img;
}

void film_release(film *f) {
    film_image_free(f->image);
    free(f->sums);
    f->image = NULL;
    f->sums = NULL;
}

void film_tile_begin(film_tile *t, film *f, int x0, int y0, int x1, int y1, int k0, int k1, thread_stats *stats,
                     _Atomic uint64_t *progress) {
    t->film = f;
    t->x0 = x0;
    t->x1 = x1;
    t->y1 = y1;
    t->k0 = k0;
    t->k1 = k1;
    t->x = x0;
    t->y = y0;
    t->k = k0;
    t->pixel = film_pixel_index(f, x0, y0);
    t->stats = stats;
    t->progress = progress;
    t->sum[0] = t->sum[1] = t->sum[2] = 0.0;
    if (k0 > 0) memcpy(t->sum, &f->sums[t->pixel * 3u], sizeof t->sum);
}
