// sampling.h — turning uniform random numbers into directions and points with known densities.
#ifndef GLINT_SAMPLING_H
#define GLINT_SAMPLING_H

#include "core/rng.h"
#include "core/vec.h"

/// Uniform point in the unit disk, by rejection (the book's method).
static inline void sample_unit_disk(rng *r, float *x, float *y) {
    for (;;) {
        float a = rng_range(r, -1.0f, 1.0f), b = rng_range(r, -1.0f, 1.0f);
        if (a * a + b * b < 1.0f) { *x = a; *y = b; return; }
    }
}

/// Uniform direction on the unit sphere, by rejection from the cube (the book's method).
static inline vec3 sample_unit_vector(rng *r) {
    for (;;) {
        vec3 p = v3(rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1));
        float l2 = v3_len2(p);
        if (l2 > 1e-30f && l2 <= 1.0f) return v3_scale(p, 1.0f / sqrtf(l2));
    }
}

/// Direction in the hemisphere around unit normal n with density cos(theta)/pi (Malley's method: a
/// uniform disk point lifted onto the hemisphere), drawn from exactly two random numbers.
static inline vec3 sample_cosine_hemisphere(rng *r, vec3 n) {
    const float two_pi = 6.28318530717959f;
    float u1 = rng_float(r), u2 = rng_float(r);
    float rad = sqrtf(u1), phi = two_pi * u2;
    float z = sqrtf(fmaxf(0.0f, 1.0f - u1));
    vec3 t, b;
    v3_basis(n, &t, &b);
    return v3_add(v3_add(v3_scale(t, rad * cosf(phi)), v3_scale(b, rad * sinf(phi))), v3_scale(n, z));
}

#endif
