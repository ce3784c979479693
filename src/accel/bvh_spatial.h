// bvh_spatial.h — spatial splits in the binary BVH build (private to the build; bvh_spatial.c): a range may be cut
// by a plane through its primitives rather than between them, a triangle that crosses the plane going to both sides
// with the box of its part on each (Stich, Friedrich and Dietrich 2009, "Spatial splits in bounding volume
// hierarchies"), where the SAH says that beats every split of whole primitives. Measured on the mesh yardstick's
// meshes (docs/architecture.md, "Spatial splits"): the few that pay are near the top of the tree, where a CAD
// model's long triangles cross the boxes of whole parts.
#ifndef GLINT_BVH_SPATIAL_H
#define GLINT_BVH_SPATIAL_H

#include "accel/bvh_sah.h"
#include "core/thread_pool.h"

/// What a build's spatial splits need: the corners of its triangles.
typedef struct bvh_spatial {
    const bvh_input *in;
} bvh_spatial;

/// Builds the binary tree over bd->prims[0, n) with object and spatial splits (bd->spatial says over what): its root
/// is node 0. bd->prims grows to make room for the triangles cut in two (BVH_SPATIAL_GROWTH times n, and the `front`
/// primitives that follow the tree's, kept); on return its leaves hold bd->prims[0, *used) and the front follows.
/// The subtrees below the spatial splits are built on the pool's threads (NULL: serially): the same tree either way.
/// False when out of memory (bd->failed; bd->prims is still the array to free).
bool bvh_build_spatial(builder *bd, size_t n, size_t front, thread_pool *pool, size_t *used);

#endif
