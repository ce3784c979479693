// bvh_collapse.h — the binary BVH collapsed into the wide one with its leaf packets (private to the build;
// bvh_collapse.c).
#ifndef GLINT_BVH_COLLAPSE_H
#define GLINT_BVH_COLLAPSE_H

#include "accel/bvh.h"
#include "core/thread_pool.h"

/// Collapses b's binary tree (`leaves` leaves over refs[0, tree), the huge spheres refs[tree, tree + front) after
/// it) into the wide BVH with its leaf packets, and frees the binary tree and the references; false when out of
/// memory (b is then for bvh_release).
bool bvh_collapse_wide(bvh *b, thread_pool *pool, size_t leaves, size_t tree, size_t front);

#endif
