// medium.h — participating media: homogeneous volumes (book 2's constant_medium, and media with RGB
// absorption and scattering coefficients) bounded by a sphere or a box, with the Henyey–Greenstein phase
// function. Book-style: a medium is an object of its own whose boundary is a closed shape; a ray finds where
// it enters and leaves the boundary, whatever surfaces lie there (book 2 puts smoke inside a glass sphere by
// giving both the same sphere).
//
// Sampling is analytic, with spectral MIS at the level of the path (the hero-channel scheme of Wilkie et al.
// 2014, as pbrt-v4 does it): each path draws one colour channel, the first time it meets a medium, and every
// free flight of the path samples its exponential distance with that channel's extinction; the path carries
// its sampling density in each channel relative to the others (medium_path.ratio), and its weight is the
// balance heuristic over the three channels of the whole path, so that a chromatic medium gives weights of at
// most 3 (times the albedo) instead of weights that multiply up bounce after bounce. For grey media (book 2's)
// it is exactly the book's estimator: an exponential distance, weight albedo at a scattering event and 1
// otherwise.
#ifndef GLINT_MEDIUM_H
#define GLINT_MEDIUM_H

#include "core/rng.h"
#include "core/vec.h"
#include "geometry/transform.h"
#include "material/texture.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// The largest coefficient (density, sigma_a, sigma_s) a medium may have: optical depths across the world's
/// extent stay finite in double and exp(-depth) simply underflows to 0.
#define MEDIUM_MAX_COEFFICIENT 1e30

typedef enum medium_shape { MEDIUM_SPHERE, MEDIUM_BOX } medium_shape;

/// A homogeneous medium inside a closed boundary (a sphere or a box in object space, placed by a transform).
typedef struct medium {
    medium_shape shape;
    vec3 center;          ///< sphere: centre (object space)
    float radius;         ///< sphere: radius > 0
    vec3 lo, hi;          ///< box: opposite corners (object space), lo < hi
    bool transformed;     ///< whether to_object applies (else object space is world space)
    mat4 to_object;       ///< world to object space (the inverse of the boundary's transform)
    vec3 sigma_t;         ///< extinction per unit length, per channel (sigma_a + sigma_s)
    vec3 sigma_s;         ///< scattering per unit length, per channel (used when albedo_texture < 0)
    int32_t albedo_texture; ///< scene texture: sigma_s = sigma_t * texture(p) at a scattering point, or -1
    float g;              ///< Henyey–Greenstein asymmetry in (-1, 1): 0 isotropic, > 0 forward scattering
} medium;

/// A path's spectral state: the channel that drives its free flights (-1 until it first meets a medium) and its
/// sampling densities in the three channels, relative to each other (any common scale).
typedef struct medium_path {
    int hero;
    vec3 ratio;
} medium_path;

/// The state of a path that has met no medium yet.
static inline medium_path medium_path_start(void) {
    medium_path mp = {-1, {1.0f, 1.0f, 1.0f}};
    return mp;
}

/// What a ray's free flight through the media found: a scattering event (at p, in media[index]) or none before
/// tmax. `weight` multiplies the path's throughput either way.
typedef struct medium_event {
    bool scattered;
    uint32_t index;
    float t;
    vec3 p;
    vec3 weight;
} medium_event;

/// The interval (t0, t1) of the line o + t d (any d != 0) that lies inside m's boundary, clipped to
/// (tmin, tmax); false when it is empty. Computed in double: the segment of a ray that starts on a
/// surface sharing the boundary (a glass sphere's inside) is found however close the origin is to it.
bool medium_segment(const medium *m, vec3 o, vec3 d, float tmin, float tmax, float *t0, float *t1);

/// Transmittance exp(-sum of sigma_t times the length inside each medium) along o + t d, tmin < t < tmax.
vec3 medium_transmittance(const medium *media, size_t count, vec3 o, vec3 d, float tmin, float tmax);

/// Draws the free flight of the ray o + t d (unit d, t in (0, tmax), tmax may be infinite) through the media,
/// for the path whose spectral state is *mp (updated): where it first scatters, if it does before tmax, and
/// the factor by which the path's throughput changes (see the file's banner). Uses one random number for each
/// medium the ray crosses, and one more to choose the path's channel the first time it crosses one.
medium_event medium_sample(const medium *media, size_t count, const texture *textures, vec3 o, vec3 d, float tmax,
                           medium_path *mp, rng *r);

/// The Henyey–Greenstein phase function for the cosine between the travel directions before and after
/// scattering (1/(4 pi) for g = 0). It integrates to 1 over the sphere; it is also the density with which
/// phase_hg_sample draws directions.
static inline float phase_hg(float g, float cos_theta) {
    const float inv_4pi = 0.0795774715459477f;
    // Isotropic (book 2's media): the formula below gives exactly 1 / (4 pi), after a square root and a division
    // on the light sample's chain.
    if (g == 0.0f && isfinite(cos_theta)) return inv_4pi;
    float denom = 1.0f + g * g - 2.0f * g * cos_theta;
    if (!(denom > 0.0f)) denom = 1e-12f; // g -> 1 and cos -> 1: the peak, kept finite
    return inv_4pi * (1.0f - g * g) / (denom * sqrtf(denom));
}

/// A direction scattered from unit travel direction d with density phase_hg(g, cos) (cos relative to d),
/// from two uniform numbers a, b in [0, 1): the inverse of HG's cumulative distribution in cos theta, a
/// uniform azimuth.
static inline vec3 phase_hg_sample(float g, vec3 d, float a, float b) {
    float cos_theta;
    if (fabsf(g) < 1e-3f) {
        cos_theta = 1.0f - 2.0f * a;
    } else {
        float s = (1.0f - g * g) / (1.0f - g + 2.0f * g * a);
        cos_theta = (1.0f + g * g - s * s) / (2.0f * g);
    }
    cos_theta = cos_theta < -1.0f ? -1.0f : cos_theta > 1.0f ? 1.0f : cos_theta;
    float sin_theta = sqrtf(f_max(0.0f, 1.0f - cos_theta * cos_theta));
    float phi = 6.28318530717959f * b;
    vec3 t, bt;
    v3_basis(d, &t, &bt);
    vec3 w = v3_add(v3_scale(d, cos_theta), v3_add(v3_scale(t, sin_theta * cosf(phi)), v3_scale(bt, sin_theta * sinf(phi))));
    return v3_unit(w);
}

#endif
