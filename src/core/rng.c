// rng.c — the out-of-line half of core/rng.h: the Sobol' sampler's draw and its values computed ahead, kept off
// PCG32's inlined path.
#include "core/rng.h"
#include "core/sobol.h"

// The sampler's offset advanced by n within the same depth field.
static void advance(rng *r, unsigned n) { r->inc = (r->inc & ~0xfffeULL) | ((r->inc + 2u * n) & 0xfffeu); }

// Where pair `pair` waits in r->ahead (its first value; the second follows), or -1 when it was not prepared.
static int ahead_slot(const rng *r, uint32_t pair) {
    uint32_t j = pair - r->ahead.base; // wraps to a large number below the base
    if (j >= 32 || !((r->ahead.pairs >> j) & 1u)) return -1;
    return 2 * __builtin_popcount(r->ahead.pairs & ((1u << j) - 1u));
}

void rng_sobol_prepare(rng *r, int depth, unsigned pairs) {
    uint32_t base = (uint32_t)(uint16_t)(depth + 1) << 14; // the depth field's offset 0 as a pair index
    r->ahead.base = base;
    r->ahead.pairs = 0;
    for (int n = 0; pairs && n < RNG_AHEAD; n++) {
        unsigned j = (unsigned)__builtin_ctz(pairs);
        pairs &= pairs - 1;
        float *v = &r->ahead.value[2 * n];
        sobol_pair_floats(r->state, (uint32_t)(r->inc >> 32), base + j, &v[0], &v[1]);
        r->ahead.pairs |= 1u << j;
    }
}

float rng_sobol_float(rng *r) {
    uint32_t dim = rng_sobol_dimension(r);
    int slot = ahead_slot(r, dim >> 1);
    float u = slot >= 0 ? r->ahead.value[slot + (int)(dim & 1u)]
                        : sobol_float(sobol_sampler_u32_reversed(r->state, (uint32_t)(r->inc >> 32), dim));
    advance(r, 1);
    return u;
}

void rng_sobol_float2(rng *r, float *a, float *b) {
    if (rng_sobol_dimension(r) & 1u) advance(r, 1); // a 2-D decision takes a whole pair: its values form nets
    uint32_t dim = rng_sobol_dimension(r);
    int slot = ahead_slot(r, dim >> 1);
    if (slot >= 0) {
        *a = r->ahead.value[slot];
        *b = r->ahead.value[slot + 1];
    } else {
        sobol_pair_floats(r->state, (uint32_t)(r->inc >> 32), dim >> 1, a, b);
    }
    advance(r, 2);
}
