// sampling.h — turning uniform random numbers into directions and points with known densities.
#ifndef GLINT_SAMPLING_H
#define GLINT_SAMPLING_H

#include "core/rng.h"
#include "core/vec.h"

#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

/// Uniform direction on the unit sphere, by rejection from the cube (the book's method).
static inline vec3 sample_unit_vector(rng *r) {
    for (;;) {
        vec3 p = v3(rng_range(r, -1, 1), rng_range(r, -1, 1), rng_range(r, -1, 1));
        float l2 = v3_len2(p);
        if (l2 > 1e-30f && l2 <= 1.0f) return v3_scale(p, 1.0f / sqrtf(l2));
    }
}

/// a * b + c, fused where the target has FMA hardware (fmaf is a slow library call elsewhere).
static inline float sampling_mad(float a, float b, float c) {
#if defined(__FMA__) || defined(FP_FAST_FMAF)
    return fmaf(a, b, c);
#else
    return a * b + c;
#endif
}

/// cos and sin of the angle 2 pi u, for u in [0, 1) (an angle in turns), to about 1 ulp and without a branch
/// or a library call: the nearest quarter turn q is split off exactly (4u - q is exact for any float u in
/// [0, 1)), the remaining angle in [-pi/4, pi/4] goes through the minimax polynomials of Cephes' sinf and
/// cosf, and the quarter turns rotate the result.
static inline __attribute__((always_inline)) void sincos_turn(float u, float *c, float *s) {
    float x = 4.0f * u;
    float q = floorf(x + 0.5f);
    float t = (x - q) * 1.57079632679490f, z = t * t;
    float sn = sampling_mad(sampling_mad(sampling_mad(-1.9515295891e-4f, z, 8.3321608736e-3f), z, -1.6666654611e-1f),
                            z * t, t);
    float cs = sampling_mad(
        sampling_mad(sampling_mad(sampling_mad(2.443315711809948e-5f, z, -1.388731625493765e-3f), z,
                                  4.166664568298827e-2f),
                     z, -0.5f),
        z, 1.0f);
    // Quarter turn k maps (cos, sin) to (cs, sn), (-sn, cs), (-cs, -sn), (sn, -cs) for k = 0, 1, 2, 3 (and 4 =
    // 0). On the bits, with masks: k is random, so compiled branches would be mispredicted half the time.
#if defined(__SSE2__)
    // In the vector registers: k, its masks and the signs never leave them (the scalar form below moves every
    // value to the integer registers and back): the bunny 1.010, the engine 1.008 (15 pairs each), same bits.
    __m128 v = _mm_setr_ps(cs, sn, 0.0f, 0.0f), swapped = _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 2, 0, 1));
    __m128i k = _mm_cvttps_epi32(_mm_set1_ps(q)), one = _mm_set1_epi32(1), two = _mm_set1_epi32(2);
    __m128 swap = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(k, one), one));
    __m128 r = _mm_or_ps(_mm_and_ps(swap, swapped), _mm_andnot_ps(swap, v));
    // The sign of the cosine from k + 1, the sine's from k: bit 1 moved to the sign bit.
    __m128i sign = _mm_slli_epi32(_mm_and_si128(_mm_add_epi32(k, _mm_setr_epi32(1, 0, 0, 0)), two), 30);
    r = _mm_xor_ps(r, _mm_castsi128_ps(sign));
    *c = _mm_cvtss_f32(r);
    *s = _mm_cvtss_f32(_mm_shuffle_ps(r, r, _MM_SHUFFLE(1, 1, 1, 1)));
#else
    uint32_t k = (uint32_t)(int)q, swap = 0u - (k & 1u), bc, bs;
    memcpy(&bc, &cs, sizeof bc);
    memcpy(&bs, &sn, sizeof bs);
    uint32_t rc = ((bs & swap) | (bc & ~swap)) ^ (((k + 1u) & 2u) << 30);
    uint32_t rs = ((bc & swap) | (bs & ~swap)) ^ ((k & 2u) << 30);
    memcpy(c, &rc, sizeof rc);
    memcpy(s, &rs, sizeof rs);
#endif
}

/// Uniform point in the unit disk from exactly two random numbers, without rejection: radius sqrt(u1), angle
/// 2 pi u2 (sincos_turn).
static inline void sample_unit_disk(rng *r, float *x, float *y) {
    float u1, u2;
    rng_float2(r, &u1, &u2);
    float c, s, rad = sqrtf(u1);
    sincos_turn(u2, &c, &s);
    *x = rad * c;
    *y = rad * s;
}

/// Uniform direction on the unit sphere from exactly two random numbers, without rejection: z = 1 - 2 u1 is
/// uniform in (-1, 1] (Archimedes: so is the height of a uniform point on the sphere), the azimuth is 2 pi u2,
/// and the radius of the circle at height z is sqrt(1 - z^2) = 2 sqrt(u1 (1 - u1)), free of cancellation.
// Always inlined: in the path tracer's lean bounce a call costs more than the sampling (gcc stopped inlining it
// once the path tracer grew).
static inline __attribute__((always_inline)) vec3 sample_sphere_uniform(rng *r) {
    float u1, u2;
    rng_float2(r, &u1, &u2);
    float c, s;
    sincos_turn(u2, &c, &s);
    float rad = 2.0f * sqrtf(u1 * (1.0f - u1));
    return v3(rad * c, rad * s, 1.0f - 2.0f * u1);
}

/// Direction in the hemisphere around unit normal n with density cos(theta)/pi (Malley's method: a
/// uniform disk point lifted onto the hemisphere), drawn from exactly two random numbers, in the frame of
/// v3_basis. (The path tracer's Lambertian uses unit(n + sample_sphere_uniform), which measured faster.)
static inline vec3 sample_cosine_hemisphere(rng *r, vec3 n) {
    float u1, u2;
    rng_float2(r, &u1, &u2);
    float c, s;
    sincos_turn(u2, &c, &s);
    float rad = sqrtf(u1), z = sqrtf(1.0f - u1); // u1 < 1: z >= 2^-12, strictly above the surface
    vec3 t, b;
    v3_basis(n, &t, &b);
    return v3_fma(v3_fma(v3_scale(n, z), t, rad * c), b, rad * s);
}

#endif
