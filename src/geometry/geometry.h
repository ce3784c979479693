// geometry.h — the geometry of a scene as one value: plain arrays of spheres, quads, meshes, instances and moving
// spheres, with the motions and the shutter. The scene makes it (scene_geometry), the accel is built over it and
// its BVHs point at it: declared once, handed on by pointer, never copied field by field.
#ifndef GLINT_GEOMETRY_H
#define GLINT_GEOMETRY_H

#include "geometry/instance.h"
#include "geometry/mesh.h"
#include "geometry/motion.h"
#include "geometry/quad.h"
#include "geometry/sphere.h"

#include <stddef.h>

/// Every primitive a structure is built over, in world space except what instances place. The arrays belong to
/// whoever made the value and must outlive what is built over it; unused arrays are NULL with count 0.
typedef struct geometry_arrays {
    const sphere *spheres;               ///< world-space spheres
    size_t sphere_count;                 ///< entries of spheres
    const quad *quads;                   ///< world-space parallelograms
    size_t quad_count;                   ///< entries of quads
    const mesh *const *meshes;           ///< meshes[i]: the triangles an INSTANCE_MESH instance with index i places
    size_t mesh_count;                   ///< entries of meshes
    const sphere *instance_spheres;      ///< the object-space spheres INSTANCE_SPHERE instances place
    const instance *instances;           ///< placements of meshes and object-space spheres
    size_t instance_count;               ///< entries of instances
    const moving_sphere *moving_spheres; ///< spheres that move while the shutter is open
    size_t moving_sphere_count;          ///< entries of moving_spheres
    const motion *motions;               ///< motions[k - 1]: how an instance with motion k moves
    float time0, time1;                  ///< the shutter: moving primitives are bounded over all of [time0, time1]
} geometry_arrays;

#endif
