// texture.c — evaluating solid, checker, Perlin noise and image textures.
#include "material/texture.h"
#include "core/rng.h"
#include "core/sampling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

texture texture_solid(vec3 color) {
    texture t;
    memset(&t, 0, sizeof t);
    t.kind = TEX_SOLID;
    t.color = color;
    return t;
}

texture texture_checker(float scale, vec3 even, vec3 odd) {
    texture t = texture_solid(v3s(0.0f));
    t.kind = TEX_CHECKER;
    t.scale = scale;
    t.even = even;
    t.odd = odd;
    return t;
}

void perlin_init(perlin *pn, uint64_t seed) {
    // The generator of a fixed (seed, "perlin") pair: the same tables on every run and every thread.
    rng r = rng_for_sample(seed, 0x7065726c696eULL, 0);
    for (int i = 0; i < 256; i++) pn->gradient[i] = sample_unit_vector(&r);
    uint8_t *perms[3] = {pn->perm_x, pn->perm_y, pn->perm_z};
    for (int k = 0; k < 3; k++) {
        uint8_t *p = perms[k];
        for (int i = 0; i < 256; i++) p[i] = (uint8_t)i;
        // Fisher-Yates shuffle, as the book's permute().
        for (int i = 255; i > 0; i--) {
            int j = (int)(rng_u32(&r) % (uint32_t)(i + 1));
            uint8_t tmp = p[i];
            p[i] = p[j];
            p[j] = tmp;
        }
    }
}

// The lattice cell of x modulo 256 and the position inside it, without overflowing an int for huge x.
static int lattice(float x, float *frac) {
    float f = floorf(x);
    *frac = x - f;
    return (int)fmodf(f, 256.0f) & 255;
}

float perlin_noise(const perlin *pn, vec3 p) {
    if (!v3_is_finite(p)) return 0.0f;
    float u, v, w;
    int i = lattice(p.x, &u), j = lattice(p.y, &v), k = lattice(p.z, &w);
    // Hermite smoothing of the interpolation weights removes the grid's visible seams.
    float uu = u * u * (3.0f - 2.0f * u), vv = v * v * (3.0f - 2.0f * v), ww = w * w * (3.0f - 2.0f * w);
    float accum = 0.0f;
    for (int di = 0; di < 2; di++)
        for (int dj = 0; dj < 2; dj++)
            for (int dk = 0; dk < 2; dk++) {
                vec3 g = pn->gradient[pn->perm_x[(i + di) & 255] ^ pn->perm_y[(j + dj) & 255] ^
                                      pn->perm_z[(k + dk) & 255]];
                vec3 weight = v3(u - (float)di, v - (float)dj, w - (float)dk);
                accum += (di ? uu : 1.0f - uu) * (dj ? vv : 1.0f - vv) * (dk ? ww : 1.0f - ww) * v3_dot(g, weight);
            }
    return accum;
}

float perlin_turbulence(const perlin *pn, vec3 p, int depth) {
    float accum = 0.0f, weight = 1.0f;
    for (int i = 0; i < depth; i++) {
        accum += weight * perlin_noise(pn, p);
        weight *= 0.5f;
        p = v3_scale(p, 2.0f);
    }
    return fabsf(accum);
}

bool texture_noise(noise_kind kind, float scale, int depth, vec3 color, uint64_t seed, texture *out) {
    texture t = texture_solid(color);
    t.kind = TEX_NOISE;
    t.noise = kind;
    t.scale = scale;
    t.depth = depth;
    t.perlin = malloc(sizeof *t.perlin);
    if (!t.perlin) return false;
    perlin_init(t.perlin, seed);
    *out = t;
    return true;
}

bool texture_noise_tables(noise_kind kind, float scale, int depth, vec3 color, const perlin *tables, texture *out) {
    if (!texture_noise(kind, scale, depth, color, 0, out)) return false;
    *out->perlin = *tables;
    return true;
}

texture texture_image(image_rgb img, texture_filter filter) {
    texture t = texture_solid(v3s(0.0f));
    t.kind = TEX_IMAGE;
    t.image = img;
    t.filter = filter;
    return t;
}

void texture_free(texture *t) {
    free(t->perlin);
    image_rgb_free(&t->image);
    *t = texture_solid(v3s(0.0f));
}

// Parity of the integer floor(x): 0 or 1, for any float (0 when not finite).
static int floor_parity(float x) {
    if (!isfinite(x)) return 0;
    return (int)fabsf(fmodf(floorf(x), 2.0f));
}

static vec3 texel(const image_rgb *img, int x, int y) {
    const float *p = img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * 3;
    return v3(p[0], p[1], p[2]);
}

static int wrap(int i, int n) {
    i %= n;
    return i < 0 ? i + n : i;
}

/// The texels a lookup at (u, v) reads, and their weights: (x0, y0) alone for the nearest filter (fx = fy = 0),
/// else the four around it, (x1, y1) the far corner, bilinear weights fx, fy.
typedef struct texel_site {
    int x0, y0, x1, y1;
    float fx, fy;
} texel_site;

static texel_site texel_site_of(const image_rgb *img, texture_filter filter, float u, float v) {
    texel_site ts = {0, 0, 0, 0, 0.0f, 0.0f};
    if (!isfinite(u)) u = 0.0f;
    if (!isfinite(v)) v = 0.0f;
    u -= floorf(u);
    v = 1.0f - (v - floorf(v)); // image rows run top to bottom, v bottom to top
    if (filter == FILTER_NEAREST) { // u = 1 - epsilon may round to width: stay inside the image
        int x = (int)(u * (float)img->width), y = (int)(v * (float)img->height);
        ts.x0 = ts.x1 = x < img->width ? x : img->width - 1;
        ts.y0 = ts.y1 = y < img->height ? y : img->height - 1;
        return ts;
    }
    // Texel centres sit at (i + 0.5) / width: there the filter returns exactly that texel.
    float x = u * (float)img->width - 0.5f, y = v * (float)img->height - 0.5f;
    float x0f = floorf(x), y0f = floorf(y);
    ts.fx = x - x0f, ts.fy = y - y0f;
    ts.x0 = wrap((int)x0f, img->width), ts.y0 = wrap((int)y0f, img->height);
    ts.x1 = wrap(ts.x0 + 1, img->width), ts.y1 = wrap(ts.y0 + 1, img->height);
    return ts;
}

static vec3 image_value(const image_rgb *img, texture_filter filter, float u, float v) {
    if (!img->pixels || img->width <= 0 || img->height <= 0) return v3(0.0f, 1.0f, 1.0f); // the book's cyan
    texel_site ts = texel_site_of(img, filter, u, v);
    if (filter == FILTER_NEAREST) return texel(img, ts.x0, ts.y0);
    vec3 top = v3_lerp(texel(img, ts.x0, ts.y0), texel(img, ts.x1, ts.y0), ts.fx);
    vec3 bottom = v3_lerp(texel(img, ts.x0, ts.y1), texel(img, ts.x1, ts.y1), ts.fx);
    return v3_lerp(top, bottom, ts.fy);
}

float texture_alpha(const texture *t, float u, float v) {
    const image_rgb *img = &t->image;
    if (t->kind != TEX_IMAGE || !img->alpha || img->width <= 0 || img->height <= 0) return 1.0f;
    texel_site ts = texel_site_of(img, t->filter, u, v);
    const float *a = img->alpha;
    size_t w = (size_t)img->width;
    float a00 = a[(size_t)ts.y0 * w + (size_t)ts.x0];
    if (t->filter == FILTER_NEAREST) return a00;
    float a10 = a[(size_t)ts.y0 * w + (size_t)ts.x1], a01 = a[(size_t)ts.y1 * w + (size_t)ts.x0];
    float a11 = a[(size_t)ts.y1 * w + (size_t)ts.x1];
    float top = a00 + (a10 - a00) * ts.fx, bottom = a01 + (a11 - a01) * ts.fx;
    return top + (bottom - top) * ts.fy;
}

vec3 texture_value(const texture *t, float u, float v, vec3 p) {
    switch (t->kind) {
    case TEX_SOLID: return t->color;
    case TEX_CHECKER: {
        float inv = 1.0f / t->scale;
        int parity = floor_parity(inv * p.x) + floor_parity(inv * p.y) + floor_parity(inv * p.z);
        return (parity & 1) ? t->odd : t->even;
    }
    case TEX_NOISE: {
        float n;
        if (t->noise == NOISE_PLAIN) n = 0.5f * (1.0f + perlin_noise(t->perlin, v3_scale(p, t->scale)));
        else if (t->noise == NOISE_TURBULENCE) n = perlin_turbulence(t->perlin, v3_scale(p, t->scale), t->depth);
        else if (t->noise == NOISE_MARBLE)
            n = 0.5f * (1.0f + sinf(t->scale * p.z + 10.0f * perlin_turbulence(t->perlin, p, t->depth)));
        else {
            vec3 s = v3_scale(p, t->scale);
            n = 0.5f * (1.0f + sinf(s.z + 10.0f * perlin_turbulence(t->perlin, s, t->depth)));
        }
        return v3_scale(t->color, isfinite(n) ? n : 0.0f);
    }
    case TEX_IMAGE: return image_value(&t->image, t->filter, u, v);
    }
    return v3s(0.0f);
}
