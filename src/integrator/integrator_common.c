// integrator_common.c — the part every integrator shares, filled in by each integrator's constructor.
#include "integrator/integrator_common.h"
#include "integrator/alpha_mask.h"

#include <stddef.h>

uint64_t integrator_stream(const render_settings *rs) {
    bool sobol = rs->integrator == INTEGRATOR_PATH && rs->sampler == SAMPLER_SOBOL;
    return sobol ? RNG_SOBOL_STREAM : rng_seed_stream(rs->seed);
}

void integrator_init(integrator *it, const glint_scene *s, const accel *a) {
    it->scene = s;
    it->accel = a;
    it->camera = s->camera;
    camera_prepare(&it->camera, s->settings.width, s->settings.height);
    it->stream = integrator_stream(&s->settings);
    it->sample = NULL;
    it->render_tile = NULL;
    it->release = NULL;
    it->alpha_masks = alpha_scene_masked(s);
}
