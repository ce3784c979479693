// hash.h — 64-bit FNV-1a over bytes given piece by piece: an identity of file contents and a checksum of
// files glint writes (not a cryptographic hash: it detects accidents, not adversaries); and SplitMix64's mixing
// of one integer, which seeds the random numbers.
#ifndef GLINT_HASH_H
#define GLINT_HASH_H

#include <stddef.h>
#include <stdint.h>

/// The value a hash starts from (FNV-1a's 64-bit offset basis).
#define HASH_START UINT64_C(14695981039346656037)

/// Continues hash h over the n bytes at data: hash_bytes(hash_bytes(HASH_START, a, n), b, m) is the hash of a
/// followed by b.
static inline uint64_t hash_bytes(uint64_t h, const void *data, size_t n) {
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * UINT64_C(1099511628211);
    return h;
}

/// Continues hash h over a 64-bit value, byte by byte from the lowest: the same on every machine.
static inline uint64_t hash_u64(uint64_t h, uint64_t v) {
    for (int i = 0; i < 8; i++, v >>= 8) h = (h ^ (v & 0xffu)) * UINT64_C(1099511628211);
    return h;
}

/// SplitMix64's finaliser: spreads nearby integers (pixel and sample indices) over all 64 bits.
static inline uint64_t hash_mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#endif
