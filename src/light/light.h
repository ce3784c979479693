// light.h — the paper's lights: ambient, point (position) and directional (vector towards the light); and spot
// lights (a point light whose intensity falls off between two cones, as glTF's KHR_lights_punctual defines it).
#ifndef GLINT_LIGHT_H
#define GLINT_LIGHT_H

#include "core/vec.h"

typedef enum light_kind { LIGHT_AMBIENT, LIGHT_POINT, LIGHT_DIRECTIONAL, LIGHT_SPOT } light_kind;

typedef struct light {
    light_kind kind;
    vec3 intensity; ///< RGB; a scalar intensity i in the scene file becomes (i, i, i)
    vec3 position;  ///< point and spot lights
    vec3 direction; ///< directional light: L, pointing from surfaces towards the light, not normalised;
                    ///< spot light: unit, the axis of its cone, the way its light travels
    float cos_inner, cos_outer; ///< spot light: cosines of the cones' half-angles, cos_inner > cos_outer
} light;

/// The scene-file name of a kind ("ambient", ...).
const char *light_kind_name(light_kind kind);

/// A spot light's share of its intensity towards -wl (wl: unit, from a surface towards the light): 1 inside the
/// inner cone, 0 outside the outer one, and between them t^2 with t linear in the cosine (glTF's recommended
/// falloff, KHR_lights_punctual).
static inline float light_spot_falloff(const light *l, vec3 wl) {
    float c = -v3_dot(l->direction, wl);
    if (c >= l->cos_inner) return 1.0f;
    if (c <= l->cos_outer) return 0.0f;
    float t = (c - l->cos_outer) / (l->cos_inner - l->cos_outer);
    return t * t;
}

#endif
