// rng.c — the out-of-line half of core/rng.h: the Sobol' sampler's draw, kept off PCG32's inlined path.
#include "core/rng.h"
#include "core/sobol.h"

// The sampler's offset advanced by n within the same depth field.
static void advance(rng *r, unsigned n) { r->inc = (r->inc & ~0xfffeULL) | ((r->inc + 2u * n) & 0xfffeu); }

float rng_sobol_float(rng *r) {
    float u = sobol_float(sobol_sampler_u32_reversed(r->state, (uint32_t)(r->inc >> 32), rng_sobol_dimension(r)));
    advance(r, 1);
    return u;
}

void rng_sobol_float2(rng *r, float *a, float *b) {
    if (rng_sobol_dimension(r) & 1u) advance(r, 1); // a 2-D decision takes a whole pair: its values form nets
    uint32_t dim = rng_sobol_dimension(r);
    sobol_pair_floats(r->state, (uint32_t)(r->inc >> 32), dim >> 1, a, b);
    advance(r, 2);
}
