// light.h — the paper's lights: ambient, point (position) and directional (vector towards the light).
#ifndef GLINT_LIGHT_H
#define GLINT_LIGHT_H

#include "core/vec.h"

typedef enum light_kind { LIGHT_AMBIENT, LIGHT_POINT, LIGHT_DIRECTIONAL } light_kind;

typedef struct light {
    light_kind kind;
    vec3 intensity; ///< RGB; a scalar intensity i in the scene file becomes (i, i, i)
    vec3 position;  ///< point light
    vec3 direction; ///< directional light: L, pointing from surfaces towards the light, not normalised
} light;

/// The scene-file name of a kind ("ambient", ...).
const char *light_kind_name(light_kind kind);

#endif
