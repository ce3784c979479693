// alpha_mask.h — alpha masks (glTF alphaMode MASK) in the closest-hit and shadow queries: a hit on a surface whose
// material is masked (material_masked) and whose alpha at the hit is below the material's cutoff does not count,
// and the ray goes on through it. Integrators call these only when the scene has a masked material
// (integrator.alpha_masks): a scene without masks traces exactly as before.
#ifndef GLINT_ALPHA_MASK_H
#define GLINT_ALPHA_MASK_H

#include "accel/accel.h"
#include "material/material.h"
#include "material/texture.h"
#include "scene/scene.h"

#include <stdbool.h>

/// Cut hits one query steps through at most; the next hit then counts whatever its alpha (a bound on the work of a
/// ray through a stack of foliage cards, where ray tracers commonly stop).
#define ALPHA_MAX_LAYERS 64

/// Whether material m's alpha mask cuts its surface away at texture coordinates (u, v) (false without a mask).
static inline bool alpha_cut_at(const material *m, const texture *textures, float u, float v) {
    if (!material_masked(m)) return false;
    float alpha = m->alpha;
    if (m->alpha_texture >= 0) alpha *= texture_alpha(&textures[m->alpha_texture], u, v);
    return alpha < m->alpha_cutoff;
}
/// Whether some material of s has an alpha mask (what integrator.alpha_masks caches).
bool alpha_scene_masked(const glint_scene *s);
/// Whether hit h of ray r (found by accel_intersect) is on a surface its material's alpha mask cuts away there.
bool alpha_cut(const glint_scene *s, const ray *r, const hit *h);
/// Closest hit of r that is not cut away: accel_intersect, then again past each cut hit. The ray stays the same
/// (origin, direction, tmax; h->t in its units): only tmin moves to the cut hit's t, and since the queries count
/// t > tmin only, that surface is not met again (nor anything at exactly the same distance).
bool alpha_intersect(const accel *a, const glint_scene *s, const ray *r, hit *h);
/// Whether anything not cut away lies on r with r->tmin < t < r->tmax: the closest hits along it in turn, as
/// alpha_intersect (a masked surface blocks only where its alpha is at least the cutoff).
bool alpha_occluded(const accel *a, const glint_scene *s, const ray *r);

#endif
