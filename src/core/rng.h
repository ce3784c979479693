// rng.h — the random numbers of one pixel sample, seeded from (scene seed, pixel, sample) alone: PCG32 (O'Neill
// 2014), a small, fast generator (the independent sampler), or the Owen-scrambled Sobol' sampler (core/sobol.h)
// in the same 16 bytes, told apart by the low bit of `inc`. Callers draw with rng_float either way; the Sobol'
// sampler gives each draw the next dimension, and rng_start_bounce and rng_decision put a path's decisions on
// dimensions of their own (no-ops for PCG32, whose draws stay exactly what they were).
#ifndef GLINT_RNG_H
#define GLINT_RNG_H

#include <stdbool.h>
#include "core/hash.h"
#include "core/sobol.h"

#include <stdint.h>

/// Pairs of Sobol' values computed ahead for one bounce (rng_prepare): at most this many of its decisions.
enum { RNG_AHEAD = 3 };

/// The Sobol' values of up to RNG_AHEAD pairs of a path's next bounce, computed while its ray is traced
/// (rng_prepare).
typedef struct rng_ahead {
    uint32_t base;  ///< the pair index (dimension / 2) of the prepared bounce's offset 0
    uint32_t pairs; ///< bit j: pair base + j is in `value` (in order of j; none for PCG32)
    float value[2 * RNG_AHEAD];
} rng_ahead;

/// PCG32: state and stream (inc, always odd). The Sobol' sampler: state is the pixel's key (rng_pixel_key), inc
/// holds the sample index with its bits reversed (bits 32-63: the index shuffle starts from it), the depth field
/// (bits 16-31: 0 for the camera, d + 1 for bounce d), the next draw's offset in it (bits 1-15) and a clear bit 0;
/// and its values computed ahead. A loop over many paths keeps the two parts apart (rng_position, rng_ahead),
/// so that PCG32's paths do not carry the second.
typedef struct rng {
    uint64_t state, inc;
    rng_ahead ahead;
} rng;

/// Where a generator stands (rng's state and inc): with an rng_ahead, all of it.
typedef struct rng_position {
    uint64_t state, inc;
} rng_position;

/// The generator of position `at` and the values computed ahead `ahead` (NULL: none; the values then stay
/// unset, as no draw reads them).
static inline rng rng_join(rng_position at, const rng_ahead *ahead) {
    rng r;
    r.state = at.state;
    r.inc = at.inc;
    if (ahead) r.ahead = *ahead;
    else r.ahead.base = r.ahead.pairs = 0;
    return r;
}

/// The position of generator r.
static inline rng_position rng_position_of(const rng *r) { return (rng_position){r->state, r->inc}; }

/// The `stream` argument (of camera_batch_make, integrator.stream) that stands for the Sobol' sampler: no PCG32
/// stream is even.
enum { RNG_SOBOL_STREAM = 0 };

/// The Sobol' sampler's dimensions of a sample: offsets in the camera's depth field, then in each bounce's
/// (rng_start_bounce). Pairs (2j, 2j + 1) are one 2-D decision's; a decision that draws more numbers than its
/// slot goes on into the next offsets, and a decision's numbers never serve another decision of the same
/// bounce.
enum rng_dimension {
    RNG_DIM_FILM = 0,        ///< camera: the film point in the pixel (2-D)
    RNG_DIM_LENS = 2,        ///< camera: the point on the lens (2-D)
    RNG_DIM_TIME = 4,        ///< camera: the time in the shutter
    RNG_DIM_BSDF = 0,        ///< bounce: the material's sampling, up to six numbers (a lobe choice, then the
                             ///< direction's: 2-D at 0, 1 where it draws no choice) or the phase function's (2-D)
    RNG_DIM_LIGHT = 7,       ///< bounce: the light chosen, then the point on it (2-D: 8, 9)
    RNG_DIM_ENVIRONMENT = 10, ///< bounce: the environment's direction (2-D)
    RNG_DIM_IMPORTANCE = 12, ///< bounce: book 3's mixture: its choice, the sphere, the direction (2-D: 14, 15)
    RNG_DIM_MEDIUM = 16,     ///< bounce: the path's hero channel (once a path), one free flight a medium crossed
};
_Static_assert(RNG_DIM_FILM % 2 == 0 && RNG_DIM_LENS % 2 == 0 && (RNG_DIM_LIGHT + 1) % 2 == 0 &&
                   RNG_DIM_ENVIRONMENT % 2 == 0 && (RNG_DIM_IMPORTANCE + 2) % 2 == 0,
               "every 2-D decision starts a pair of dimensions");

/// PCG32's next 32 bits (a PCG32 generator only: rng_for_key, rng_for_sample).
static inline uint32_t rng_u32(rng *r) {
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

/// SplitMix64 finaliser: spreads nearby integers (pixel and sample indices) over the state space.
static inline uint64_t rng_mix64(uint64_t z) { return hash_mix64(z); }

/// The stream (increment) of every generator of a render with this seed: the part of rng_for_sample that
/// depends on the seed alone.
static inline uint64_t rng_seed_stream(uint64_t seed) { return (rng_mix64(seed ^ 0x9e3779b97f4a7c15ULL) << 1u) | 1u; }

/// The part of rng_for_sample that depends on (seed, pixel) alone, so that a render loop computes it once a pixel.
static inline uint64_t rng_pixel_key(uint64_t seed, uint64_t pixel) { return rng_mix64(seed + pixel * 0x632be59bd9b4e019ULL); }

/// rng_for_sample from its precomputed parts: stream = rng_seed_stream(seed), key = rng_pixel_key(seed, pixel).
static inline rng rng_for_key(uint64_t stream, uint64_t key, uint64_t sample) {
    rng r = {.state = 0, .inc = stream};
    uint64_t init = rng_mix64(key ^ (sample + 0x2545f4914f6cdd1dULL));
    rng_u32(&r);
    r.state += init;
    rng_u32(&r);
    return r;
}

/// The generator for one pixel sample: a pure function of (seed, pixel index, sample index).
static inline rng rng_for_sample(uint64_t seed, uint64_t pixel, uint64_t sample) {
    return rng_for_key(rng_seed_stream(seed), rng_pixel_key(seed, pixel), sample);
}

/// The Sobol' sampler of sample `sample` of the pixel of key `key` (rng_pixel_key), at the camera's first
/// dimension.
static inline rng rng_sobol(uint64_t key, uint64_t sample) {
    return (rng){.state = key, .inc = (uint64_t)sobol_reverse_bits((uint32_t)sample) << 32};
}

/// The generator of sample `sample` of the pixel of key `key` in a render of stream `stream`: PCG32
/// (rng_for_key), or the Sobol' sampler where the stream is RNG_SOBOL_STREAM.
static inline rng rng_for_stream(uint64_t stream, uint64_t key, uint64_t sample) {
    return stream == RNG_SOBOL_STREAM ? rng_sobol(key, sample) : rng_for_key(stream, key, sample);
}

/// Whether r is the Sobol' sampler (not PCG32).
static inline bool rng_is_sobol(const rng *r) { return (r->inc & 1u) == 0; }

/// Tells the compiler that r is a PCG32 generator (the caller knows): the inlined draws after it lose their
/// Sobol' branch, while r (a local whose `inc` nothing changes) keeps the fact.
static inline void rng_assume_pcg(const rng *r) {
    if (rng_is_sobol(r)) __builtin_unreachable();
}

/// The dimension (depth field and offset: core/sobol.h's `dim`) of a Sobol' sampler's next draw.
static inline uint32_t rng_sobol_dimension(const rng *r) { return (uint32_t)(r->inc >> 1) & 0x7fffffffu; }

/// The Sobol' sampler's next value, its offset advanced (core/rng.c: out of line, off PCG32's path).
float rng_sobol_float(rng *r);

/// Uniform float in [0, 1): the top 24 bits, so 1.0 is never returned. PCG32's next number, or the Sobol'
/// sampler's value of its next dimension.
// Always inlined: PCG32's step is a few instructions, and a call costs more (gcc stopped inlining it once the
// Sobol' branch was added). No branch hint: the Sobol' sampler is the default, PCG32 the yardsticks' choice.
static inline __attribute__((always_inline)) float rng_float(rng *r) {
    if (rng_is_sobol(r)) return rng_sobol_float(r);
    return (float)(rng_u32(r) >> 8) * 0x1.0p-24f;
}

/// A path's bounce `depth` (0: the first surface or medium event) starts: the Sobol' sampler's next draws are
/// that bounce's, from offset 0. Nothing for PCG32.
static inline void rng_start_bounce(rng *r, int depth) {
    if (rng_is_sobol(r)) r->inc = (r->inc & 0xffffffff00000000ULL) | ((uint64_t)(uint16_t)(depth + 1) << 16);
}

/// The next draws are decision `offset`'s (an rng_dimension) of the current bounce (or of the camera). Nothing
/// for PCG32.
static inline void rng_decision(rng *r, int offset) {
    if (rng_is_sobol(r)) r->inc = (r->inc & ~0xfffeULL) | (((uint64_t)offset << 1) & 0xfffeu);
}

/// The Sobol' sampler's next pair of dimensions (from the next even offset: a pair's values form (0,m,2)-nets,
/// two values of different pairs do not), sharing one hash and one shuffle; the offset moves past it (core/rng.c).
void rng_sobol_float2(rng *r, float *a, float *b);

/// Two uniform floats in [0, 1) for one 2-D decision: PCG32's next two (what rng_float draws twice), or the
/// Sobol' sampler's next pair of dimensions, skipping an odd offset (rng_sobol_float2).
static inline __attribute__((always_inline)) void rng_float2(rng *r, float *a, float *b) {
    if (rng_is_sobol(r)) {
        rng_sobol_float2(r, a, b);
        return;
    }
    *a = (float)(rng_u32(r) >> 8) * 0x1.0p-24f;
    *b = (float)(rng_u32(r) >> 8) * 0x1.0p-24f;
}

/// The bits of rng_prepare's `pairs`: the pair of a bounce's offset 2 j is bit j.
enum rng_ahead_pair {
    RNG_AHEAD_BSDF = 1u << (RNG_DIM_BSDF / 2),
    RNG_AHEAD_LIGHT = 1u << ((RNG_DIM_LIGHT + 1) / 2), ///< the point on the light (not the light's choice)
    RNG_AHEAD_ENVIRONMENT = 1u << (RNG_DIM_ENVIRONMENT / 2),
    RNG_AHEAD_MEDIUM = 1u << (RNG_DIM_MEDIUM / 2), ///< the hero channel or a first free flight, and the next one
};

/// The Sobol' sampler's pairs `pairs` (rng_ahead_pair bits; the first RNG_AHEAD of them) of bounce `depth`
/// computed now (core/rng.c).
void rng_sobol_prepare(rng *r, int depth, unsigned pairs);

/// Before the ray that reaches bounce `depth` is traced: the Sobol' values that bounce will draw first
/// (`pairs`: rng_ahead_pair bits) are computed now, beside the traversal, instead of on the path's critical
/// chain (each pair is a chain of about 80 cycles, which a path then waited for). The same values either way.
/// Nothing for PCG32.
static inline void rng_prepare(rng *r, int depth, unsigned pairs) {
    if (rng_is_sobol(r)) rng_sobol_prepare(r, depth, pairs);
}

/// Uniform float in [lo, hi).
static inline float rng_range(rng *r, float lo, float hi) { return lo + (hi - lo) * rng_float(r); }

#endif
