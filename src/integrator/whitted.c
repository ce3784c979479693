// whitted.c — the paper's Whitted ray tracer (exact) and its colour-correct variant.
#include "integrator/integrator.h"

vec3 whitted_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts) {
    (void)s; (void)x; (void)y; (void)sample; (void)r; (void)ts;
    return v3s(0.0f); // TODO(whitted helper)
}
