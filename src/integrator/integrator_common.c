// integrator_common.c — the part every integrator shares, filled in by each integrator's constructor.
#include "integrator/integrator_common.h"
#include "integrator/alpha_mask.h"

#include <stddef.h>

void integrator_init(integrator *it, const glint_scene *s, const accel *a) {
    it->scene = s;
    it->accel = a;
    it->camera = s->camera;
    camera_prepare(&it->camera, s->settings.width, s->settings.height);
    it->stream = rng_seed_stream(s->settings.seed);
    it->sample = NULL;
    it->render_tile = NULL;
    it->release = NULL;
    it->alpha_masks = alpha_scene_masked(s);
}
