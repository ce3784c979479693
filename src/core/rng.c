// rng.c — the out-of-line half of core/rng.h: the Sobol' sampler's draw, kept off PCG32's inlined path.
#include "core/rng.h"
#include "core/sobol.h"

float rng_sobol_float(rng *r) {
    float u = sobol_sampler_float(r->state, (uint32_t)(r->inc >> 32), rng_sobol_dimension(r));
    r->inc = (r->inc & ~0xfffeULL) | ((r->inc + 2u) & 0xfffeu); // the next offset of the same depth field
    return u;
}
