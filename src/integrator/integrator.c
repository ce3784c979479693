// integrator.c — dispatch to the integrator the scene chose, and shading data of a hit.
#include "integrator/integrator.h"

vec3 integrator_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts) {
    switch (s->settings.integrator) {
    case INTEGRATOR_WHITTED: return whitted_sample(s, x, y, sample, r, ts);
    case INTEGRATOR_PATH: return path_sample(s, x, y, sample, r, ts);
    }
    return v3s(0.0f);
}
