// bvh_traverse.c — closest-hit and any-hit traversal of the wide BVH, one ray at a time: nearest child first with
// a small stack, box tests of all eight children at once and sphere and triangle packets in one SIMD pass
// (bvh_wide.h, bvh_simd.h), or the portable scalar path computing the same values; instances enter their mesh's
// BVH in object space (bvh_wide.c). Rays 64 at a time: bvh_stream.c; coherent packets of 16: bvh_packet.c.
#include "accel/bvh_wide.h"

// The closest-hit and any-hit entry points, one function per combination so that each is compiled
// for exactly its case (the sphere-only and triangle-only ones contain no call at all).
static inline __attribute__((always_inline)) bool wide_query(const bvh *b, const ray *r, hit *h, bool any, bool simd,
                                                             int leaves, uint32_t *occluder) {
    hit best = bvh_no_hit(r);
    if (!wide_run(b, r, &best, HIT_NO_INSTANCE, any, simd, leaves, occluder)) return false;
    if (!any) *h = best;
    return true;
}

static bool closest_spheres(const bvh *b, const ray *r, hit *h) {
    return wide_query(b, r, h, false, BVH_SIMD, LEAVES_SPHERES, NULL);
}
static bool closest_triangles(const bvh *b, const ray *r, hit *h) {
    return wide_query(b, r, h, false, BVH_SIMD, LEAVES_TRIANGLES, NULL);
}
static bool closest_generic(const bvh *b, const ray *r, hit *h) {
    return wide_query(b, r, h, false, BVH_SIMD, LEAVES_ANY, NULL);
}
static bool any_spheres(const bvh *b, const ray *r, uint32_t *occluder) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, LEAVES_SPHERES, occluder);
}
static bool any_triangles(const bvh *b, const ray *r, uint32_t *occluder) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, LEAVES_TRIANGLES, occluder);
}
static bool any_generic(const bvh *b, const ray *r, uint32_t *occluder) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, LEAVES_ANY, occluder);
}

bool bvh_intersect_scalar(const bvh *b, const ray *r, hit *h) {
    return wide_query(b, r, h, false, false, LEAVES_ANY, NULL);
}

bool bvh_occluded_scalar(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, false, LEAVES_ANY, NULL);
}

bool bvh_intersect(const bvh *b, const ray *r, hit *h) {
    if (b->spheres_only) return closest_spheres(b, r, h);
    return b->triangles_only ? closest_triangles(b, r, h) : closest_generic(b, r, h);
}

bool bvh_occluded(const bvh *b, const ray *r, uint32_t *occluder) {
    if (b->spheres_only) return any_spheres(b, r, occluder);
    return b->triangles_only ? any_triangles(b, r, occluder) : any_generic(b, r, occluder);
}
