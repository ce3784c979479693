// alpha_mask.c — stepping closest-hit and shadow queries through the parts of surfaces an alpha mask cuts away.
#include "integrator/alpha_mask.h"
#include "integrator/surface.h"

bool alpha_scene_masked(const glint_scene *s) {
    for (size_t i = 0; i < s->material_count; i++)
        if (material_masked(&s->materials[i])) return true;
    return false;
}

bool alpha_cut(const glint_scene *s, const ray *r, const hit *h) {
    surface sf = surface_at(s, r, h);
    return alpha_cut_at(&s->materials[sf.material], s->textures, sf.u, sf.v);
}

bool alpha_intersect(const accel *a, const glint_scene *s, const ray *r, hit *h) {
    ray rest = *r;
    for (int layer = 0; layer < ALPHA_MAX_LAYERS; layer++) {
        if (!accel_intersect(a, &rest, h)) return false;
        if (!alpha_cut(s, &rest, h)) return true;
        rest.tmin = h->t;
    }
    return accel_intersect(a, &rest, h);
}

bool alpha_occluded(const accel *a, const glint_scene *s, const ray *r) {
    hit h;
    return alpha_intersect(a, s, r, &h);
}
