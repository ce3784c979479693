// film.h — the image being rendered: per-pixel sums of samples taken in index order, the mean of each pixel's
// completed samples, and the display encoding of linear values.
#ifndef GLINT_FILM_H
#define GLINT_FILM_H

#include "glint.h"
#include "core/stats.h"
#include "core/vec.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/// How linear radiance becomes an 8-bit value: none (clamp only), gamma 2 (square root), or sRGB.
typedef enum output_transform { TRANSFORM_LINEAR, TRANSFORM_GAMMA2, TRANSFORM_SRGB } output_transform;

/// The rendered image (the public glint_image): linear RGB means and how they are displayed.
struct glint_image {
    int width, height;
    float *rgb;                 ///< linear RGB, 3 floats a pixel, row 0 at the top
    output_transform transform; ///< how rgb becomes 8-bit values
    int x0, y0;                 ///< where pixel (0, 0) lies in the full image (0, 0 unless a region)
    int full_width, full_height; ///< the full image this one is a region of (width, height unless a region)
};

/// A black image; NULL when out of memory.
glint_image *film_image_new(int width, int height, output_transform encoding);
/// Whether img is a region of a larger image rather than a whole image.
bool film_image_is_region(const glint_image *img);
/// Frees an image (NULL is allowed).
void film_image_free(glint_image *img);

/// Display encoding of one linear value: transform, clamp to [0,1], round to nearest of 0..255.
uint8_t film_encode(float linear, output_transform encoding);
/// A linear value that film_encode turns into exactly `byte` under `encoding` (decoding 8-bit images).
float film_decode(uint8_t byte, output_transform encoding);

/// A film: the image of means, and each pixel's running sum in double between sample passes, so that the
/// final mean is bit for bit the plain sum over samples 0..spp-1 in index order divided by spp.
typedef struct film {
    glint_image *image;
    double *sums; ///< RGB sums of the samples completed in earlier passes; NULL when one pass renders them all
    int spp;      ///< samples per pixel of the whole render
    bool keep_all_sums; ///< the last pass stores its sums too (for a checkpoint), not only the earlier ones
    int x0, y0;   ///< the image's origin in full-image pixels: tiles are given in full-image coordinates
} film;

/// A black film of the region [x0, x0 + width) x [y0, y0 + height) of a full_width x full_height image;
/// `passes` > 1 keeps running sums. False when out of memory (f is then empty).
bool film_init(film *f, const int region[4], int full_width, int full_height, int spp, int passes,
               output_transform encoding);
/// Makes the film keep every pixel's sums after every pass, the last included, as a checkpoint needs them;
/// false when out of memory for them.
bool film_keep_all_sums(film *f);
/// Sets the image to the mean of each pixel's counts[i] samples whose sums the film holds (a resumed
/// render: exactly what the passes that took them stored); pixels of no sample stay black.
void film_restore_means(film *f, const uint32_t *counts);
/// Hands the image over to the caller; the film no longer owns it.
glint_image *film_take_image(film *f);
/// Frees what the film still owns.
void film_release(film *f);

/// The samples of one tile pass, delivered in order (rows of pixels, each pixel's samples k0..k1-1 in index
/// order): film_tile_add sums them, drops NaN and infinite ones (counted), and stores each pixel's mean as
/// soon as its samples of the pass are complete.
typedef struct film_tile {
    film *film;
    int x0, x1, y1, k0, k1; ///< the pass: pixels [x0, x1) of rows up to y1, samples [k0, k1)
    int x, y, k;            ///< the next sample's pixel and index
    size_t pixel;           ///< the film's index of (x, y): (y - y0) * width + (x - x0)
    double sum[3];          ///< the current pixel's sum so far
    thread_stats *stats;    ///< counts samples and discarded samples
    _Atomic uint64_t *progress; ///< the samples counter the progress reporter reads
} film_tile;

/// Starts a tile pass: samples [k0, k1) of the pixels [x0, x1) x [y0, y1) (full-image coordinates, inside
/// the film's region), counted in *stats and *progress.
void film_tile_begin(film_tile *t, film *f, int x0, int y0, int x1, int y1, int k0, int k1, thread_stats *stats,
                     _Atomic uint64_t *progress);

/// Stores in the image the mean of a pixel's k > 0 samples whose sum is `sum`.
static inline void film_store_mean(film *f, size_t pixel, const double sum[3], int k) {
    float *px = &f->image->rgb[pixel * 3u];
    double inv = 1.0 / k; // one division for the three channels, at every pass of every pixel
    for (int c = 0; c < 3; c++) px[c] = (float)(sum[c] * inv);
}

/// Stores a pixel's state after its samples [0, k) (k1: the end of this pass): its running sum for the next
/// pass, and the mean of its samples so far in the image.
static inline void film_store_pixel(film *f, size_t pixel, const double sum[3], int k, int k1) {
    if (f->sums && (k1 < f->spp || f->keep_all_sums)) memcpy(&f->sums[pixel * 3u], sum, 3 * sizeof *sum);
    if (k > 0) film_store_mean(f, pixel, sum, k);
}

/// The index in the film's image of full-image pixel (x, y).
static inline size_t film_pixel_index(const film *f, int x, int y) {
    return (size_t)(y - f->y0) * (size_t)f->image->width + (size_t)(x - f->x0);
}

/// Adds the next sample of the tile pass; false once the pass is complete.
static inline bool film_tile_add(film_tile *t, vec3 c) {
    t->stats->samples++;
    atomic_store_explicit(t->progress, t->stats->samples, memory_order_relaxed);
    // A NaN or infinite sample would poison the pixel: drop it (it counts as black), count it, report it.
    if (!v3_is_finite(c)) t->stats->discarded_samples++;
    else {
        t->sum[0] += c.x;
        t->sum[1] += c.y;
        t->sum[2] += c.z;
    }
    if (++t->k < t->k1) return true;
    film_store_pixel(t->film, t->pixel, t->sum, t->k1, t->k1); // this pixel's samples of the pass are done
    t->k = t->k0;
    if (++t->x == t->x1) {
        t->x = t->x0;
        t->y++;
    }
    if (t->y == t->y1) return false;
    t->pixel = film_pixel_index(t->film, t->x, t->y);
    t->sum[0] = t->sum[1] = t->sum[2] = 0.0;
    if (t->k0 > 0) memcpy(t->sum, &t->film->sums[t->pixel * 3u], sizeof t->sum);
    return true;
}

/// Ends a tile pass cut short by a stop request: the current pixel keeps the mean of the samples it completed,
/// the pixels not reached keep the previous pass's.
static inline void film_tile_stop(film_tile *t) { film_store_pixel(t->film, t->pixel, t->sum, t->k, t->k1); }

#endif
