// path.c — the path tracer of "Ray Tracing in One Weekend", iterative.
#include "integrator/integrator.h"

vec3 path_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts) {
    (void)s; (void)x; (void)y; (void)sample; (void)r; (void)ts;
    return v3s(0.0f); // TODO(path helper)
}
