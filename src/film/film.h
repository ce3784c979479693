// film.h — the image being rendered: per-pixel sums of samples taken in index order, the mean of each pixel's
// completed samples, and the display encoding of linear values.
#ifndef GLINT_FILM_H
#define GLINT_FILM_H

#include "core/status.h"
#include "core/stats.h"
#include "core/vec.h"

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/// How linear radiance becomes an 8-bit value: none (clamp only), gamma 2 (square root), or sRGB.
typedef enum output_transform { TRANSFORM_LINEAR, TRANSFORM_GAMMA2, TRANSFORM_SRGB } output_transform;
enum { TRANSFORM_COUNT = TRANSFORM_SRGB + 1 };
/// Their names, in order ("linear", "gamma2", "srgb"): the scene's "output", --output-encoding, checkpoints.
extern const char *const output_transform_names[TRANSFORM_COUNT];

/// The AOVs a film can keep (the bits of glint_aov), in the order of glint_image.aov[].
enum { FILM_AOV_ALBEDO, FILM_AOV_NORMAL, FILM_AOV_DEPTH, FILM_AOV_SAMPLES, FILM_AOV_COUNT };
/// Every AOV bit (bit i: plane FILM_AOV i, as glint_aov's bits are).
#define FILM_AOV_MASK_ALL ((1u << FILM_AOV_COUNT) - 1u)

/// Floats a pixel of AOV plane i (FILM_AOV_*): 3 for albedo RGB and normal XYZ, 1 for depth Z and the sample count.
static inline int film_aov_channels(int i) { return i == FILM_AOV_DEPTH || i == FILM_AOV_SAMPLES ? 1 : 3; }

/// The rendered image: linear RGB means and how they are displayed. The API hands it out as the opaque
/// glint_image, under this tag.
typedef struct glint_image glint_image;
struct glint_image {
    int width, height;
    float *rgb;                 ///< linear RGB, 3 floats a pixel, row 0 at the top
    float *aov[FILM_AOV_COUNT]; ///< the AOV planes rendered (film_aov_channels floats a pixel), NULL for the others
    output_transform transform; ///< how rgb becomes 8-bit values
    int x0, y0;                 ///< where pixel (0, 0) lies in the full image (0, 0 unless a region)
    int full_width, full_height; ///< the full image this one is a region of (width, height unless a region)
};

/// A black image; NULL when out of memory.
glint_image *film_image_new(int width, int height, output_transform encoding);
/// Adds zeroed planes for the AOVs of mask (glint_aov bits) that img lacks; false when out of memory.
bool film_image_add_aovs(glint_image *img, unsigned mask);
/// Whether img is a region of a larger image rather than a whole image.
bool film_image_is_region(const glint_image *img);
/// Frees an image (NULL is allowed).
void film_image_free(glint_image *img);

/// Display encoding of one linear value: transform, clamp to [0,1], round to nearest of 0..255.
uint8_t film_encode(float linear, output_transform encoding);
/// The whole image display-encoded into out (width * height * 3 bytes): film_encode of every value, exactly,
/// through a table of the 255 values where the byte changes (fast enough for a live preview).
void film_encode_image(const glint_image *img, uint8_t *out);
/// A linear value that film_encode turns into exactly `byte` under `encoding` (decoding 8-bit images).
float film_decode(uint8_t byte, output_transform encoding);

/// What an integrator reports of one sample besides its colour, for the AOVs (arbitrary output variables): the
/// albedo and the world-space shading normal (facing the ray) of the surface it saw first (after following
/// perfect mirrors and glass, in the path tracer), and the camera distance of the first hit (INFINITY: none).
typedef struct film_aov_sample {
    vec3 albedo, normal;
    float depth;
} film_aov_sample;

/// Doubles a pixel of the AOV running sums: albedo RGB, normal XYZ, the sum of the finite depths, and their
/// count (the depth plane is their mean: the mean distance of the samples that hit something).
enum { FILM_AOV_SUM_ALBEDO = 0, FILM_AOV_SUM_NORMAL = 3, FILM_AOV_SUM_DEPTH = 6, FILM_AOV_SUM_HITS = 7,
       FILM_AOV_STRIDE = 8 };

/// A film: the image of means, and each pixel's running sum in double between sample passes, so that the
/// final mean is bit for bit the plain sum over samples 0..spp-1 in index order divided by spp. The AOVs are
/// summed the same way, beside the colour, when asked for. A checkpoint of the render is sums, aov_sums (when
/// not NULL) and the passes completed: the image's means follow from them.
typedef struct film {
    glint_image *image;
    double *sums;     ///< RGB sums of the samples completed in earlier passes; NULL when one pass renders them all
    double *aov_sums; ///< FILM_AOV_STRIDE doubles a pixel, as sums; NULL without AOVs or with a single pass
    double *odd_sums; ///< adaptive sampling: RGB sums of the odd-numbered samples alone, kept as sums; else NULL
    unsigned aovs;    ///< the AOVs kept (glint_aov bits); 0: none, and no AOV work at all
    int spp;          ///< samples per pixel of the whole render
    bool keep_all_sums; ///< the last pass stores its sums too (for a checkpoint), not only the earlier ones
    int x0, y0;       ///< the image's origin in full-image pixels: tiles are given in full-image coordinates
} film;

/// A black film of the region [x0, x0 + width) x [y0, y0 + height) of a full_width x full_height image, with
/// the AOV planes of `aovs` (glint_aov bits); `passes` > 1 keeps running sums. False when out of memory (f is
/// then empty).
bool film_init(film *f, const int region[4], int full_width, int full_height, int spp, int passes,
               output_transform encoding, unsigned aovs);
/// Makes the film keep every pixel's sums after every pass, the last included, as a checkpoint needs them;
/// false when out of memory for them.
bool film_keep_all_sums(film *f);
/// Adaptive sampling decides a pixel's fate at sample counts that are powers of two of at least this.
enum { FILM_ADAPTIVE_MIN_SAMPLES = 16 };

/// Adaptive sampling's estimate of the relative error of pixel `pixel` after its first `count` samples, from the
/// film's sums and odd-numbered samples' sums (film_keep_odd_sums): with E and O the means of its even- and
/// odd-numbered samples and I the mean of all, sum_c |E_c - O_c| / 2 / (1e-4 + sqrt(sum_c I_c)) over R, G, B
/// (Cycles' measure: the difference of the two interleaved half-buffers, relative to the square root of the
/// pixel's brightness). `count` must be even and positive.
double film_pixel_error(const film *f, size_t pixel, uint32_t count);
/// Whether adaptive sampling stops pixel `pixel` once it has `count` samples: count is a power of two of at
/// least FILM_ADAPTIVE_MIN_SAMPLES (a pass boundary) and film_pixel_error is below `threshold`. A function of the
/// pixel's own sums alone, so the same for any thread count, region, tile order or resume.
bool film_pixel_converged(const film *f, size_t pixel, uint32_t count, float threshold);

/// Makes the film keep, beside every pixel's sums, the sums of its odd-numbered samples (samples 1, 3, 5, ...),
/// zeroed: the two interleaved half-buffers adaptive sampling estimates a pixel's error from. False when out of
/// memory.
bool film_keep_odd_sums(film *f);
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
    double odd[3];          ///< the current pixel's sum of odd-numbered samples so far (when the film keeps them)
    double aov_sum[FILM_AOV_STRIDE]; ///< the current pixel's AOV sums so far (when the film keeps AOVs)
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

/// Stores a pixel's AOV state after its samples [0, k): running sums, and means in the image's planes.
void film_store_aov_pixel(film *f, size_t pixel, const double sum[FILM_AOV_STRIDE], int k, int k1);

/// Stores a pixel's state after its samples [0, k) (k1: the end of this pass): its running sum for the next
/// pass (after the last one too when a checkpoint keeps them), and the mean of its samples so far in the image;
/// the same for the AOV sums (t's) when the film keeps them.
static inline void film_store_pixel(film *f, size_t pixel, const double sum[3], const double *aov_sum, int k, int k1) {
    if (f->sums && (k1 < f->spp || f->keep_all_sums)) memcpy(&f->sums[pixel * 3u], sum, 3 * sizeof *sum);
    if (k > 0) film_store_mean(f, pixel, sum, k);
    if (f->aovs) film_store_aov_pixel(f, pixel, aov_sum, k, k1); // once a pixel and pass: no cost per sample
}

/// Starts the odd-numbered samples' sums of the tile's current pixel: zero, or what earlier passes left.
static inline void film_tile_load_odd(film_tile *t) {
    if (t->k0 > 0) memcpy(t->odd, &t->film->odd_sums[t->pixel * 3u], sizeof t->odd);
    else t->odd[0] = t->odd[1] = t->odd[2] = 0.0;
}

/// Stores the tile's current pixel: film_store_pixel, and its odd-numbered samples' sums when the film keeps them.
static inline void film_tile_store(film_tile *t, int k) {
    film_store_pixel(t->film, t->pixel, t->sum, t->aov_sum, k, t->k1);
    if (t->film->odd_sums) memcpy(&t->film->odd_sums[t->pixel * 3u], t->odd, sizeof t->odd);
}

/// Starts the AOV sums of the tile's current pixel: zero, or what earlier passes left.
static inline void film_tile_load_aovs(film_tile *t) {
    if (t->k0 > 0 && t->film->aov_sums)
        memcpy(t->aov_sum, &t->film->aov_sums[t->pixel * FILM_AOV_STRIDE], sizeof t->aov_sum);
    else
        memset(t->aov_sum, 0, sizeof t->aov_sum);
}

/// The index in the film's image of full-image pixel (x, y).
static inline size_t film_pixel_index(const film *f, int x, int y) {
    return (size_t)(y - f->y0) * (size_t)f->image->width + (size_t)(x - f->x0);
}

/// Stores the tile's current pixel, whose samples of the pass are done, and moves to the next; false once the pass
/// is complete (film_tile_add's rare part, out of line so that the per-sample part stays small enough to inline).
bool film_tile_next_pixel(film_tile *t);

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
        if ((t->k & 1) && t->film->odd_sums) { // the odd half-buffer (adaptive sampling): taken in index order too
            t->odd[0] += c.x;
            t->odd[1] += c.y;
            t->odd[2] += c.z;
        }
    }
    if (++t->k < t->k1) return true;
    return film_tile_next_pixel(t);
}

/// film_tile_add for a film that keeps AOVs: adds the sample's AOVs to the pixel's, then its colour. Non-finite
/// albedos or normals are dropped (as black), a non-finite depth counts as a miss.
static inline bool film_tile_add_aov(film_tile *t, vec3 c, const film_aov_sample *a) {
    double *s = t->aov_sum;
    if (v3_is_finite(a->albedo)) {
        s[FILM_AOV_SUM_ALBEDO] += a->albedo.x;
        s[FILM_AOV_SUM_ALBEDO + 1] += a->albedo.y;
        s[FILM_AOV_SUM_ALBEDO + 2] += a->albedo.z;
    }
    if (v3_is_finite(a->normal)) {
        s[FILM_AOV_SUM_NORMAL] += a->normal.x;
        s[FILM_AOV_SUM_NORMAL + 1] += a->normal.y;
        s[FILM_AOV_SUM_NORMAL + 2] += a->normal.z;
    }
    if (isfinite(a->depth)) {
        s[FILM_AOV_SUM_DEPTH] += a->depth;
        s[FILM_AOV_SUM_HITS] += 1.0;
    }
    return film_tile_add(t, c);
}

/// Ends a tile pass cut short by a stop request: the current pixel keeps the mean of the samples it completed,
/// the pixels not reached keep the previous pass's.
static inline void film_tile_stop(film_tile *t) { film_tile_store(t, t->k); }

#endif
