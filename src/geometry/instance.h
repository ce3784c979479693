// instance.h — one placement of shared geometry (a mesh, or a sphere under a general transform) with its own
// transform: the link between the scene's geometry arrays and the two-level acceleration structure.
#ifndef GLINT_INSTANCE_H
#define GLINT_INSTANCE_H

#include "geometry/motion.h"
#include "geometry/transform.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/// What an instance places: a mesh (its triangles) or a single sphere, in object space.
typedef enum instance_kind { INSTANCE_MESH, INSTANCE_SPHERE } instance_kind;

/// One placement of shared geometry with its own transform: meshes are loaded once and placed many
/// times; a sphere under a transform that is not a similarity becomes an instance too.
typedef struct instance {
    instance_kind kind;
    uint32_t index;   ///< the mesh (index into the mesh list) or the object-space sphere it places
    transform xf;     ///< xf.m: object to world; xf.inv: world to object
    int32_t material; ///< overrides every triangle's material, or -1: the mesh's own materials
    uint32_t motion;  ///< 0: xf places it at every time; k > 0: it moves by the scene's motions[k - 1] (xf is then
                      ///< its pose at time 0, and everything that places it asks motion_at for the ray's time)
    // What shading asks of xf.m at every hit, made once by instance_cache (scene_add_instance):
    float stretch;         ///< mat4_stretch(&xf.m)
    bool keeps_directions; ///< mat4_keeps_directions(&xf.m)
} instance;

/// The infinity norm of m's linear part (its largest row sum of magnitudes): the most it stretches a length.
static inline float mat4_stretch(const mat4 *m) {
    float norm = 0.0f, k;
    for (int i = 0; i < 3; i++) {
        const float *row = m->m[i];
        norm = (k = fabsf(row[0]) + fabsf(row[1]) + fabsf(row[2])) > norm ? k : norm;
    }
    return norm;
}

/// Whether m's linear part is a positive multiple of the identity (a placement by scale and translation): it
/// turns no direction, so object-space unit normals are already the world's.
static inline bool mat4_keeps_directions(const mat4 *m) {
    float k = m->m[0][0];
    return k > 0.0f && m->m[1][1] == k && m->m[2][2] == k && m->m[0][1] == 0.0f && m->m[0][2] == 0.0f &&
           m->m[1][0] == 0.0f && m->m[1][2] == 0.0f && m->m[2][0] == 0.0f && m->m[2][1] == 0.0f;
}

/// Fills in what the instance caches of its transform (after xf is set).
static inline void instance_cache(instance *in) {
    in->stretch = mat4_stretch(&in->xf.m);
    in->keeps_directions = mat4_keeps_directions(&in->xf.m);
}

#endif
