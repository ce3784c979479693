// film.c — the rendered image, the running sums behind it, and the conversion of linear values to 8 bits.
#include "film/film.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

glint_image *film_image_new(int width, int height, output_transform encoding) {
    glint_image *img = malloc(sizeof *img);
    if (!img) return NULL;
    img->width = width;
    img->height = height;
    img->transform = encoding;
    img->x0 = img->y0 = 0;
    img->full_width = width;
    img->full_height = height;
    for (int i = 0; i < FILM_AOV_COUNT; i++) img->aov[i] = NULL;
    img->rgb = calloc((size_t)width * (size_t)height * 3u, sizeof(float));
    if (!img->rgb) {
        free(img);
        return NULL;
    }
    return img;
}

bool film_image_add_aovs(glint_image *img, unsigned mask) {
    size_t pixels = (size_t)img->width * (size_t)img->height;
    for (int i = 0; i < FILM_AOV_COUNT; i++) {
        if (!(mask & (1u << i)) || img->aov[i]) continue;
        img->aov[i] = calloc(pixels * (size_t)film_aov_channels(i), sizeof(float));
        if (!img->aov[i]) return false;
    }
    return true;
}

bool film_image_is_region(const glint_image *img) {
    return img->x0 != 0 || img->y0 != 0 || img->width != img->full_width || img->height != img->full_height;
}

void film_image_free(glint_image *img) {
    if (!img) return;
    free(img->rgb);
    for (int i = 0; i < FILM_AOV_COUNT; i++) free(img->aov[i]);
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

const char *const output_transform_names[TRANSFORM_COUNT] = {"linear", "gamma2", "srgb"};

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

// The exact encoder of a whole image. film_encode is non-decreasing in its argument, so the byte of a value in
// (0, 1) is the number of thresholds at or below it, threshold b being the smallest float that encodes to b or
// more; positive floats compare as their bits do. A value starts from the byte of the first float of its bucket
// (2^16 consecutive floats) and rarely passes more than one threshold from there: no powf per value.
enum {
    ENCODE_ONE_BITS = 0x3F800000,                     // the bits of 1.0f: from there on every value encodes to 255
    ENCODE_BUCKET_SHIFT = 16,
    ENCODE_BUCKETS = ENCODE_ONE_BITS >> ENCODE_BUCKET_SHIFT,
};
typedef struct encode_table {
    uint32_t threshold[257];        ///< bits of the smallest float encoding to >= b; [256] lies past every float
    uint8_t bucket[ENCODE_BUCKETS]; ///< the byte of the float whose bits are k << ENCODE_BUCKET_SHIFT
} encode_table;

static uint32_t float_bits(float v) {
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

static float bits_float(uint32_t u) {
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static void encode_table_build(encode_table *t, output_transform encoding) {
    t->threshold[0] = 0;
    for (unsigned b = 1; b < 256; b++) { // bisection: 30 film_encode calls a byte
        uint32_t lo = t->threshold[b - 1], hi = ENCODE_ONE_BITS; // film_encode(1.0f) is 255
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (film_encode(bits_float(mid), encoding) >= b) hi = mid;
            else lo = mid + 1;
        }
        t->threshold[b] = lo;
    }
    t->threshold[256] = UINT32_MAX;
    unsigned b = 0;
    for (uint32_t k = 0; k < ENCODE_BUCKETS; k++) {
        while (t->threshold[b + 1] <= k << ENCODE_BUCKET_SHIFT) b++;
        t->bucket[k] = (uint8_t)b;
    }
}

static uint8_t encode_with(const encode_table *t, float v) {
    if (!(v > 0.0f)) return 0; // as film_encode: NaN is black too
    uint32_t u = float_bits(v);
    if (u >= ENCODE_ONE_BITS) return 255;
    unsigned b = t->bucket[u >> ENCODE_BUCKET_SHIFT];
    while (u >= t->threshold[b + 1]) b++;
    return (uint8_t)b;
}

void film_encode_image(const glint_image *img, uint8_t *out) {
    encode_table t;
    encode_table_build(&t, img->transform);
    size_t n = (size_t)img->width * (size_t)img->height * 3u;
    for (size_t i = 0; i < n; i++) out[i] = encode_with(&t, img->rgb[i]);
}

bool film_init(film *f, const int region[4], int full_width, int full_height, int spp, int passes,
               output_transform encoding, unsigned aovs) {
    int width = region[2] - region[0], height = region[3] - region[1];
    f->spp = spp;
    f->sums = NULL;
    f->aov_sums = NULL;
    f->odd_sums = NULL;
    f->aovs = aovs & ((1u << FILM_AOV_COUNT) - 1u);
    f->keep_all_sums = false;
    f->x0 = region[0];
    f->y0 = region[1];
    f->image = film_image_new(width, height, encoding);
    if (!f->image) return false;
    f->image->x0 = region[0];
    f->image->y0 = region[1];
    f->image->full_width = full_width;
    f->image->full_height = full_height;
    size_t pixels = (size_t)width * (size_t)height;
    bool ok = film_image_add_aovs(f->image, f->aovs);
    if (ok && passes > 1) {
        f->sums = malloc(pixels * 3u * sizeof *f->sums);
        if (f->aovs) f->aov_sums = malloc(pixels * FILM_AOV_STRIDE * sizeof *f->aov_sums);
        ok = f->sums && (!f->aovs || f->aov_sums);
    }
    if (!ok) film_release(f);
    return ok;
}

void film_store_aov_pixel(film *f, size_t pixel, const double sum[FILM_AOV_STRIDE], int k, int k1) {
    if (f->aov_sums && k1 < f->spp) memcpy(&f->aov_sums[pixel * FILM_AOV_STRIDE], sum, FILM_AOV_STRIDE * sizeof *sum);
    if (k <= 0) return;
    double inv = 1.0 / k;
    float *const *plane = f->image->aov;
    // Albedo and normal are plain means (a normal is not renormalised: OIDN takes the mean as it is).
    for (int i = 0; i < 2; i++) {
        if (!plane[i]) continue;
        const double *s = &sum[i == FILM_AOV_ALBEDO ? FILM_AOV_SUM_ALBEDO : FILM_AOV_SUM_NORMAL];
        for (int c = 0; c < 3; c++) plane[i][pixel * 3u + (size_t)c] = (float)(s[c] * inv);
    }
    // Depth: the mean over the samples that hit a surface; a pixel where none did is infinitely far.
    if (plane[FILM_AOV_DEPTH]) {
        double hits = sum[FILM_AOV_SUM_HITS];
        plane[FILM_AOV_DEPTH][pixel] = hits > 0.0 ? (float)(sum[FILM_AOV_SUM_DEPTH] / hits) : INFINITY;
    }
    if (plane[FILM_AOV_SAMPLES]) plane[FILM_AOV_SAMPLES][pixel] = (float)k; // the samples the pixel has taken
}

bool film_keep_all_sums(film *f) {
    f->keep_all_sums = true;
    size_t n = (size_t)f->image->width * (size_t)f->image->height * 3u;
    // Zeroed: a checkpoint written before every pixel had a pass holds defined bytes for them.
    if (f->sums) memset(f->sums, 0, n * sizeof *f->sums);
    else f->sums = calloc(n, sizeof *f->sums);
    return f->sums != NULL;
}

bool film_keep_odd_sums(film *f) {
    f->odd_sums = calloc((size_t)f->image->width * (size_t)f->image->height * 3u, sizeof *f->odd_sums);
    return f->odd_sums != NULL;
}

double film_pixel_error(const film *f, size_t pixel, uint32_t count) {
    const double *sum = &f->sums[pixel * 3u], *odd = &f->odd_sums[pixel * 3u];
    double half = (double)count / 2.0, difference = 0.0, brightness = 0.0;
    for (int c = 0; c < 3; c++) {
        difference += fabs((sum[c] - odd[c]) - odd[c]) / half;
        brightness += sum[c] / (double)count;
    }
    return 0.5 * difference / (1e-4 + sqrt(brightness > 0.0 ? brightness : 0.0));
}

bool film_pixel_converged(const film *f, size_t pixel, uint32_t count, float threshold) {
    if (count < FILM_ADAPTIVE_MIN_SAMPLES || (count & (count - 1u)) != 0) return false;
    return film_pixel_error(f, pixel, count) < (double)threshold;
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
    free(f->aov_sums);
    free(f->odd_sums);
    f->image = NULL;
    f->sums = NULL;
    f->aov_sums = NULL;
    f->odd_sums = NULL;
}

// Starts the tile's current pixel (t->x, t->y) at the pass's first sample: its sums, odd-numbered samples' sums and
// AOV sums are zero, or what earlier passes left.
static void film_tile_start_pixel(film_tile *t) {
    t->k = t->k0;
    t->pixel = film_pixel_index(t->film, t->x, t->y);
    t->sum[0] = t->sum[1] = t->sum[2] = 0.0;
    if (t->k0 > 0) memcpy(t->sum, &t->film->sums[t->pixel * 3u], sizeof t->sum);
    if (t->film->odd_sums) film_tile_load_odd(t);
    film_tile_load_aovs(t);
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
    t->stats = stats;
    t->progress = progress;
    film_tile_start_pixel(t);
}

bool film_tile_next_pixel(film_tile *t) {
    film_tile_store(t, t->k1);
    if (++t->x == t->x1) {
        t->x = t->x0;
        t->y++;
    }
    if (t->y == t->y1) return false;
    film_tile_start_pixel(t);
    return true;
}
