// envmap.c — equirectangular environment lights: the direction-to-texel mapping and its inverse, and
// sampling directions in proportion to the radiance they bring.
#include "light/envmap.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double pi = 3.14159265358979323846;

envmap envmap_make(image_rgb img, float scale, float rotate_degrees) {
    double r = (double)rotate_degrees * pi / 180.0;
    envmap e = {img, scale, (float)cos(r), (float)sin(r)};
    return e;
}

void envmap_free(envmap *e) { image_rgb_free(&e->image); }

// The map's own frame: d turned back by the rotation about +y (the rotation by -angle).
static vec3 to_map(const envmap *e, vec3 d) {
    return v3(e->rotate_cos * d.x - e->rotate_sin * d.z, d.y, e->rotate_sin * d.x + e->rotate_cos * d.z);
}

// The texel (column, row) that direction d (unit, in the map's frame) falls in.
static void texel_of(const envmap *e, vec3 d, int *col, int *row) {
    int w = e->image.width, h = e->image.height;
    double phi = atan2((double)d.x, -(double)d.z), y = d.y < -1.0f ? -1.0 : (d.y > 1.0f ? 1.0 : d.y);
    double u = (phi / (2.0 * pi) + 0.5) * w, v = acos(y) / pi * h;
    int c = (int)u, r = (int)v;
    *col = c < 0 ? 0 : (c >= w ? w - 1 : c);
    *row = r < 0 ? 0 : (r >= h ? h - 1 : r);
}

static vec3 texel(const envmap *e, int col, int row) {
    const float *p = &e->image.pixels[((size_t)row * (size_t)e->image.width + (size_t)col) * 3u];
    return v3(p[0] * e->scale, p[1] * e->scale, p[2] * e->scale);
}

vec3 envmap_radiance(const envmap *e, vec3 d) {
    if (!e->image.pixels || !v3_is_finite(d)) return v3s(0.0f);
    int col, row;
    texel_of(e, to_map(e, d), &col, &row);
    return texel(e, col, row);
}

void envmap_sampler_release(envmap_sampler *s) {
    free(s->row_cdf);
    free(s->col_cdf);
    free(s->texel_pdf);
    memset(s, 0, sizeof *s);
}

bool envmap_sampler_build(envmap_sampler *s, const envmap *e) {
    memset(s, 0, sizeof *s);
    int w = e->image.width, h = e->image.height;
    if (!e->image.pixels || w <= 0 || h <= 0) return false;
    size_t n = (size_t)w * (size_t)h;
    s->row_cdf = malloc((size_t)h * sizeof *s->row_cdf);
    s->col_cdf = malloc(n * sizeof *s->col_cdf);
    s->texel_pdf = malloc(n * sizeof *s->texel_pdf);
    double *row_sum = calloc((size_t)h, sizeof *row_sum);
    if (!s->row_cdf || !s->col_cdf || !s->texel_pdf || !row_sum) {
        free(row_sum);
        envmap_sampler_release(s);
        return false;
    }
    s->width = w;
    s->height = h;
    // Weights: luminance times sin(theta) at the row's centre (the solid angle a texel of that row covers).
    double total = 0.0;
    for (int r = 0; r < h; r++) {
        double sin_t = sin(pi * (r + 0.5) / h), acc = 0.0;
        for (int c = 0; c < w; c++) {
            vec3 l = texel(e, c, r);
            double y = 0.2126 * l.x + 0.7152 * l.y + 0.0722 * l.z;
            acc += isfinite(y) && y > 0.0 ? y * sin_t : 0.0;
            s->col_cdf[(size_t)r * (size_t)w + (size_t)c] = (float)acc; // the row's running sum, normalised below
        }
        row_sum[r] = acc;
        total += acc;
    }
    if (!(total > 0.0) || !isfinite(total)) {
        free(row_sum);
        envmap_sampler_release(s);
        return false;
    }
    double acc = 0.0;
    for (int r = 0; r < h; r++) {
        acc += row_sum[r];
        s->row_cdf[r] = r == h - 1 ? 1.0f : (float)(acc / total);
    }
    // Conditional cdfs normalised per row, texel probabilities from the cdf steps (so that what
    // envmap_sample draws and what envmap_pdf reports agree exactly).
    for (int r = 0; r < h; r++) {
        float *cdf = &s->col_cdf[(size_t)r * (size_t)w];
        float row_p = s->row_cdf[r] - (r ? s->row_cdf[r - 1] : 0.0f);
        float prev = 0.0f;
        for (int c = 0; c < w; c++) {
            float v = row_sum[r] > 0.0 ? (c == w - 1 ? 1.0f : (float)(cdf[c] / row_sum[r])) : (float)(c + 1) / (float)w;
            cdf[c] = v;
            s->texel_pdf[(size_t)r * (size_t)w + (size_t)c] = row_p * (v - prev);
            prev = v;
        }
    }
    free(row_sum);
    return true;
}

// The first index of cdf[0..n) whose value exceeds x (the last when none does).
static int find_interval(const float *cdf, int n, float x) {
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (x < cdf[mid]) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

// Density per unit solid angle of texel (col, row) chosen with probability p and a direction uniform over
// its (phi, theta) rectangle: p / (area in (phi, theta)) / sin(theta), the texel's area being (2 pi / W)(pi / H).
static float texel_density(const envmap_sampler *s, float p, double sin_t) {
    if (!(p > 0.0f) || !(sin_t > 0.0)) return 0.0f;
    return (float)((double)p * s->width * s->height / (2.0 * pi * pi * sin_t));
}

bool envmap_sample(const envmap_sampler *s, const envmap *e, float a, float b, vec3 *wi, float *pdf, vec3 *radiance) {
    int row = find_interval(s->row_cdf, s->height, a);
    int col = find_interval(&s->col_cdf[(size_t)row * (size_t)s->width], s->width, b);
    // Where in the texel: a and b rescaled within the intervals they fell in (uniform there).
    float r0 = row ? s->row_cdf[row - 1] : 0.0f, r1 = s->row_cdf[row];
    const float *cdf = &s->col_cdf[(size_t)row * (size_t)s->width];
    float c0 = col ? cdf[col - 1] : 0.0f, c1 = cdf[col];
    double fv = r1 > r0 ? (a - r0) / (r1 - r0) : 0.5, fu = c1 > c0 ? (b - c0) / (c1 - c0) : 0.5;
    double theta = pi * (row + fv) / s->height, phi = 2.0 * pi * ((col + fu) / s->width - 0.5);
    double sin_t = sin(theta);
    *pdf = texel_density(s, s->texel_pdf[(size_t)row * (size_t)s->width + (size_t)col], sin_t);
    if (!(*pdf > 0.0f) || !isfinite(*pdf)) {
        *pdf = 0.0f;
        return false;
    }
    vec3 m = v3((float)(sin_t * sin(phi)), (float)cos(theta), (float)(-sin_t * cos(phi))); // in the map's frame
    // Back to the world: the rotation about +y by the angle, (x, z) -> (x cos + z sin, -x sin + z cos).
    *wi = v3(e->rotate_cos * m.x + e->rotate_sin * m.z, m.y, -e->rotate_sin * m.x + e->rotate_cos * m.z);
    *radiance = texel(e, col, row);
    return true;
}

float envmap_pdf(const envmap_sampler *s, const envmap *e, vec3 d) {
    vec3 m = to_map(e, d);
    int col, row;
    texel_of(e, m, &col, &row);
    double y = m.y < -1.0f ? -1.0 : (m.y > 1.0f ? 1.0 : m.y), sin_t = sqrt(fmax(0.0, 1.0 - y * y));
    return texel_density(s, s->texel_pdf[(size_t)row * (size_t)s->width + (size_t)col], sin_t);
}
