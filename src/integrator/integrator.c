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

bool integrator_tile_by_samples(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts) {
    const render_settings *rs = &it->scene->settings;
    for (int y = tp->y0; y < tp->y1; y++)
        for (int x = tp->x0; x < tp->x1; x++) {
            // rng_for_sample(seed, pixel, k), its per-render and per-pixel parts computed once.
            uint64_t key = rng_pixel_key(rs->seed, (uint64_t)y * (uint64_t)rs->width + (uint64_t)x);
            for (int k = tp->k0; k < tp->k1; k++) {
                if (tile_pass_stopping(tp)) {
                    film_tile_stop(ft);
                    return false;
                }
                rng r = rng_for_key(it->stream, key, (uint64_t)k);
                film_tile_add(ft, it->sample(it, x, y, (uint32_t)k, &r, ts));
            }
        }
    return true;
}
