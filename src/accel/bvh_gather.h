// bvh_gather.h — the BVH build's input (private to the build; bvh_gather.c): every primitive's box and reference,
// long, slanted triangles pre-split into pieces, the huge spheres set apart, the references made in place.
#ifndef GLINT_BVH_GATHER_H
#define GLINT_BVH_GATHER_H

#include "accel/bvh_sah.h"
#include "core/thread_pool.h"

/// Gathers the primitives of in (whose geometry is not NULL: a bvh's adopted input) into prims (returning how
/// many), their box in *all, and whether they are all triangles and quads in *triangles_only.
size_t bvh_gather_prims(const bvh_input *in, build_prim *prims, thread_pool *pool, box3 *all, bool *triangles_only);
/// Box bb padded by 2^-19 of its largest coordinate, conservative for the slab test (a box computed with rounding:
/// clipped or transformed geometry).
box3 bvh_box_padded(bounds3 bb);
/// The corners of triangle reference r (of in's mesh or of a flattened instance).
void bvh_prim_triangle(const bvh_input *in, prim_ref r, vec3 p[3]);
/// Splits the long, slanted triangles among (*prims)[0, n) into pieces (tri_split.h); returns the new count.
size_t bvh_presplit(const bvh_input *in, build_prim **prims, size_t n, thread_pool *pool);
/// Moves the huge spheres to the end of prims[0, n) (tested after the wide tree); returns how many.
size_t bvh_split_front(build_prim *prims, size_t n, const box3 *all);
/// Turns the build input into the primitive references, in place and in order.
prim_ref *bvh_refs_in_place(build_prim *prims, size_t n);

#endif
