// brute_force.h — closest-hit and any-hit queries that test every primitive of a geometry value (private to
// src/accel and the tests): the reference for the BVHs, and --accel none.
#ifndef GLINT_BRUTE_FORCE_H
#define GLINT_BRUTE_FORCE_H

#include "accel/accel.h"

/// Closest hit among the primitives of in by testing every one, ties broken as the BVHs break them. flat[i], when
/// flat and it are not NULL, is instance i's mesh in world space (accel_build flattened it): its triangles are
/// tested there, as the BVHs test them.
bool brute_force_intersect(const geometry_arrays *in, const mesh *const *flat, const ray *r, hit *h);
/// Whether any primitive of in lies on the ray, by testing every one (flat as for brute_force_intersect).
bool brute_force_occluded(const geometry_arrays *in, const mesh *const *flat, const ray *r);

#endif
