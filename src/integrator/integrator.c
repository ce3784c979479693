// integrator.c — choosing and building the integrator a scene asks for, and the sample-by-sample tile loop.
#include "integrator/integrator.h"

#include <stddef.h>
#include <stdlib.h>

integrator *integrator_create(const glint_scene *s, const accel *a, const integrator_options *o, glint_error *err) {
    switch (s->settings.integrator) {
    case INTEGRATOR_WHITTED: return whitted_create(s, a, err);
    case INTEGRATOR_PATH: return path_create(s, a, !(o && o->no_light_sampling), err);
    }
    return NULL;
}

void integrator_free(integrator *it) {
    if (!it) return;
    if (it->release) it->release(it);
    else free(it);
}

void integrator_init(integrator *it, const glint_scene *s, const accel *a) {
    it->scene = s;
    it->accel = a;
    it->camera = s->camera;
    camera_prepare(&it->camera, s->settings.width, s->settings.height);
    it->stream = rng_seed_stream(s->settings.seed);
    it->sample = NULL;
    it->render_tile = NULL;
    it->release = NULL;
}
