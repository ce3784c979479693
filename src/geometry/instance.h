// instance.h — one placement of shared geometry (a mesh, or a sphere under a general transform) with its own
// transform: the link between the scene's geometry arrays and the two-level acceleration structure.
#ifndef GLINT_INSTANCE_H
#define GLINT_INSTANCE_H

#include "geometry/motion.h"
#include "geometry/transform.h"

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
} instance;

#endif
