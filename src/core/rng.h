// rng.h — PCG32 (O'Neill 2014): a small, fast generator seeded from (scene seed, pixel, sample) alone.
#ifndef GLINT_RNG_H
#define GLINT_RNG_H

#include <stdint.h>

typedef struct rng {
    uint64_t state, inc;
} rng;

static inline uint32_t rng_u32(rng *r) {
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

/// SplitMix64 finaliser: spreads nearby integers (pixel and sample indices) over the state space.
static inline uint64_t rng_mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/// The stream (increment) of every generator of a render with this seed: the part of rng_for_sample that
/// depends on the seed alone.
static inline uint64_t rng_seed_stream(uint64_t seed) { return (rng_mix64(seed ^ 0x9e3779b97f4a7c15ULL) << 1u) | 1u; }

/// The part of rng_for_sample that depends on (seed, pixel) alone, so that a render loop computes it once a pixel.
static inline uint64_t rng_pixel_key(uint64_t seed, uint64_t pixel) { return rng_mix64(seed + pixel * 0x632be59bd9b4e019ULL); }

/// rng_for_sample from its precomputed parts: stream = rng_seed_stream(seed), key = rng_pixel_key(seed, pixel).
static inline rng rng_for_key(uint64_t stream, uint64_t key, uint64_t sample) {
    rng r;
    r.state = 0;
    r.inc = stream;
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

/// Uniform float in [0, 1): the top 24 bits, so 1.0 is never returned.
static inline float rng_float(rng *r) { return (float)(rng_u32(r) >> 8) * 0x1.0p-24f; }

/// Uniform float in [lo, hi).
static inline float rng_range(rng *r, float lo, float hi) { return lo + (hi - lo) * rng_float(r); }

#endif
