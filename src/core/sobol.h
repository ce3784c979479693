// sobol.h — Sobol' points and the path tracer's low-discrepancy sampler built on them: each 2-D decision of a
// sample (film point, lens point, BSDF direction, point on a light, ...) takes Sobol' dimensions 0 and 1, a
// (0,2)-sequence, at the pixel's sample index shuffled for that decision (Burley 2020's nested uniform
// scramble of the index, seeded by pixel and decision), and each value is Owen-scrambled on its own (a hashed
// nested uniform scramble, seeded by pixel and dimension). So the first 2^m samples of any pixel form a
// (0,m,2)-net in every decision's pair of dimensions, the pixels' errors are independent, and every value is a
// pure function of (pixel key, sample index, dimension): the same for any thread count, tile order or machine.
#ifndef GLINT_SOBOL_H
#define GLINT_SOBOL_H

#include "core/hash.h"

#include <stdint.h>
#if defined(__GFNI__) && defined(__SSE2__)
#include <immintrin.h>
#endif

/// Dimensions of the Sobol' sequence whose generator matrices sobol_matrix builds (Joe & Kuo's first ten).
enum { SOBOL_DIMENSIONS = 10 };

/// The generator matrix of Sobol' dimension dim (< SOBOL_DIMENSIONS): columns[k] is the 32-bit fraction that
/// bit k of a point's index adds (by XOR) to its coordinate.
void sobol_matrix(int dim, uint32_t columns[32]);
/// The unscrambled coordinate dim (< SOBOL_DIMENSIONS) of point `index` (natural order, not Gray code), as a
/// 32-bit fraction: the XOR of the columns of the index's set bits.
uint32_t sobol_point(uint32_t index, int dim);

/// x with its 32 bits in reverse order.
static inline uint32_t sobol_reverse_bits(uint32_t x) {
#if defined(__GFNI__) && defined(__SSE2__)
    // One affine transform over GF(2) reverses each byte's bits (the matrix with ones on the anti-diagonal), a
    // byte swap the bytes: three instructions for the shift-and-mask steps below (the pair draw 1.8x the
    // throughput). The same bits either way.
    __m128i v = _mm_cvtsi32_si128((int)x);
    v = _mm_gf2p8affine_epi64_epi8(v, _mm_set1_epi64x((long long)0x8040201008040201ULL), 0);
    return __builtin_bswap32((uint32_t)_mm_cvtsi128_si32(v));
#else
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x >> 8) & 0x00ff00ffu);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
    x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
    return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
#endif
}

/// Sobol' dimension 1 with its bits reversed: digit j of the coordinate is the XOR of the index bits k whose
/// positions contain j's (k AND j = j), as the generator matrix of x + 1 is Pascal's triangle mod 2 (Lucas'
/// theorem); that superset sum takes five shift-and-mask steps, one per bit of a position.
static inline uint32_t sobol_dim1_reversed(uint32_t index) {
    index ^= (index >> 1) & 0x55555555u;
    index ^= (index >> 2) & 0x33333333u;
    index ^= (index >> 4) & 0x0f0f0f0fu;
    index ^= (index >> 8) & 0x00ff00ffu;
    return index ^ ((index >> 16) & 0x0000ffffu);
}

/// A nested uniform (Owen) scramble of bit-reversed x: each bit is flipped by a hash of the bits below it (the
/// higher digits of the unreversed value) and the seed. Every step (x ^= x * even, x += seed, x *= odd) changes
/// bit k by a function of bits 0..k-1 alone, so a digit's flip depends on the digits above it only, as Owen's
/// scrambling asks; the multipliers are Vegdahl's improvement of Laine and Karras's hash.
static inline uint32_t sobol_owen_reversed(uint32_t x, uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/// The hash of one 2-D decision (dimensions 2 * pair and 2 * pair + 1) of the pixel of key `key` (rng_pixel_key):
/// its low half seeds the shuffle of the sample index, its high half the scramble of the pair's first value.
static inline uint64_t sobol_pair_hash(uint64_t key, uint32_t pair) {
    return hash_mix64(key ^ ((uint64_t)pair * 0x9e3779b97f4a7c15ULL));
}

/// The pair's shuffled index from the sample index with its bits reversed (a nested uniform scramble of the
/// index's bits read from the top, so the first 2^m indices map onto one aligned block of 2^m, which is a
/// (0,m,2)-net of Sobol' dimensions 0 and 1).
static inline uint32_t sobol_pair_index(uint64_t pair_hash, uint32_t reversed_sample) {
    return sobol_reverse_bits(sobol_owen_reversed(reversed_sample, (uint32_t)pair_hash));
}

/// Value `which` (0 or 1) of a pair at its shuffled index, as a 32-bit fraction: Sobol' dimension `which`,
/// Owen-scrambled with a seed of its own (the second value's from one more SplitMix64 round).
static inline uint32_t sobol_pair_value(uint64_t pair_hash, uint32_t index, unsigned which) {
    // The coordinate with its bits reversed: Sobol' dimension 0 is the reversed index itself.
    uint32_t v = which ? sobol_dim1_reversed(index) : index;
    uint32_t seed = (uint32_t)((which ? hash_mix64(pair_hash) : pair_hash) >> 32);
    return sobol_reverse_bits(sobol_owen_reversed(v, seed));
}

/// The sampler's value of dimension `dim` (rng_sobol_dimension: the depth field and the offset) of the sample
/// whose index has its bits reversed (what the sampler keeps: the shuffle starts from it) of the pixel of key
/// `key` (rng_pixel_key), as a 32-bit fraction. The dimensions 2j and 2j + 1 of a depth are a pair (one 2-D
/// decision): one shuffle of the index, Sobol' dimensions 0 and 1.
static inline uint32_t sobol_sampler_u32_reversed(uint64_t key, uint32_t reversed_sample, uint32_t dim) {
    uint64_t h = sobol_pair_hash(key, dim >> 1);
    return sobol_pair_value(h, sobol_pair_index(h, reversed_sample), dim & 1u);
}

/// sobol_sampler_u32_reversed of sample index `sample`.
static inline uint32_t sobol_sampler_u32(uint64_t key, uint32_t sample, uint32_t dim) {
    return sobol_sampler_u32_reversed(key, sobol_reverse_bits(sample), dim);
}

/// A 32-bit fraction as a float in [0, 1): its top 24 bits, as rng_float takes PCG32's.
static inline float sobol_float(uint32_t u) { return (float)(u >> 8) * 0x1.0p-24f; }

/// Both values of pair `pair` (dimensions 2 pair and 2 pair + 1) of the sample whose index has its bits reversed,
/// as floats: one hash and one shuffle for the two.
static inline void sobol_pair_floats(uint64_t key, uint32_t reversed_sample, uint32_t pair, float *a, float *b) {
    uint64_t h = sobol_pair_hash(key, pair);
    uint32_t index = sobol_pair_index(h, reversed_sample);
    *a = sobol_float(sobol_pair_value(h, index, 0));
    *b = sobol_float(sobol_pair_value(h, index, 1));
}

/// sobol_sampler_u32 as a float in [0, 1): its top 24 bits, as rng_float takes PCG32's.
static inline float sobol_sampler_float(uint64_t key, uint32_t sample, uint32_t dim) {
    return sobol_float(sobol_sampler_u32(key, sample, dim));
}

#endif
