// bvh_traverse.c — closest-hit and any-hit traversal of the wide BVH, one ray at a time: nearest child first with
// a small stack, box tests of all eight children at once and sphere and triangle packets in one SIMD pass
// (bvh_wide.h, bvh_simd.h), or the portable scalar path computing the same values; instances enter their mesh's
// BVH in object space (bvh_prim.h). Rays 64 at a time: bvh_stream.c; coherent packets of 16: bvh_packet.c.
#include "accel/bvh_prim.h"
#include "accel/bvh_wide.h"

__attribute__((noinline)) hit bvh_packet_hit(const bvh *b, const bvh_index_packet *p, const ray *r, tri_cache *tc,
                                             hit best, uint32_t inst_id, bool any, trav_mode mode, bool *hit_any) {
    *hit_any = false;
    for (uint32_t k = 0; k < p->h.count; k++) {
        if (!prim_hit(b, p->h.kind, p->prim[k], HIT_NO_INSTANCE, r, tc, &best, inst_id, any, mode)) continue;
        *hit_any = true;
        if (any) break;
    }
    return best;
}

// One ray through a wide BVH from its root, improving *best; true when anything was hit. With `leaves` not
// LEAVES_ANY, the code for other kinds, with its out-of-line calls (around which every vector register would
// have to be saved), is left out.
static inline __attribute__((always_inline)) bool wide_run(const bvh *b, const ray *r, hit *best, uint32_t inst_id,
                                                           bool any, bool simd, int leaves) {
    if (b->root == BVH_EMPTY && b->front == BVH_EMPTY) return false;
    trav_ray tr;
    simd_ray sr;
    simd_tri stri;
    if (simd) {
        if (!simd_setup(r, &sr, leaves == LEAVES_TRIANGLES)) return false;
    } else {
        if (ray_is_nan(r)) return false;
        tr = trav_setup(r);
    }
    tri_cache tc = {.ready = false};
    // A triangle-only BVH tests triangles in nearly every leaf: their constants are made once, up front.
    if (simd && leaves == LEAVES_TRIANGLES) {
        tri_for(&tc, r);
        simd_tri_setup(&tc.tr, r->tmin, r->tmax, &stri);
    }
    bool found = false;
    // In a sphere-only BVH the huge spheres are one sphere packet. Its test does not depend on the tree's, so
    // a closest-hit query makes it first, where the processor overlaps it with the first tree steps, and
    // merges its hits after the tree (+1.3 to +1.6% on rtiow-final; docs/benchmarks.md).
    bool front_first = simd && !any && leaves == LEAVES_SPHERES && b->front != BVH_EMPTY;
    front_spheres front = {0};
    if (front_first) front_spheres_test(b, &sr, &front);
    if (b->root != BVH_EMPTY) {
        stack_entry stack[WIDE_STACK];
        walk w = {b->root, 0};
        int st;
        while ((st = wide_step(b, r, &tr, &sr, &stri, &tc, stack, &w, best, inst_id, &found, any, simd, leaves)) ==
               STEP_MORE) {
        }
        if (st == STEP_FOUND) return true;
    }
    if (front_first) {
        if (front_spheres_offer(&front, best, inst_id)) found = true;
        return found;
    }
    // The huge spheres after the tree (bvh_split_front), against the tree's nearest hit.
    if (b->front != BVH_EMPTY) {
        bool h;
        if (simd) h = leaf_simd(b, b->front, r, &sr, &stri, &tc, best, inst_id, any, leaves);
        else h = leaf_scalar(b, b->front, r, &tc, best, inst_id, any, leaves);
        found = found || h;
    }
    return found;
}

// An instance's BLAS (bvh_prim.h), by the path of the wide traversal that entered it.
static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    switch (mode) {
    case MODE_WIDE_SIMD: // a mesh's BVH holds only triangles
        if (blas->triangles_only) return wide_run(blas, r, best, inst_id, any, BVH_SIMD, LEAVES_TRIANGLES);
        return wide_run(blas, r, best, inst_id, any, BVH_SIMD, LEAVES_ANY);
    case MODE_WIDE_SCALAR: return wide_run(blas, r, best, inst_id, any, false, LEAVES_ANY);
    case MODE_BINARY: break; // the binary BVH's instances: bvh2_traverse.c
    }
    return false;
}

// The closest-hit and any-hit entry points, one function per combination so that each is compiled
// for exactly its case (the sphere-only and triangle-only ones contain no call at all).
static inline __attribute__((always_inline)) bool wide_query(const bvh *b, const ray *r, hit *h, bool any, bool simd,
                                                             int leaves) {
    hit best = bvh_no_hit(r);
    if (!wide_run(b, r, &best, HIT_NO_INSTANCE, any, simd, leaves)) return false;
    if (!any) *h = best;
    return true;
}

static bool closest_spheres(const bvh *b, const ray *r, hit *h) {
    return wide_query(b, r, h, false, BVH_SIMD, LEAVES_SPHERES);
}
static bool closest_triangles(const bvh *b, const ray *r, hit *h) {
    return wide_query(b, r, h, false, BVH_SIMD, LEAVES_TRIANGLES);
}
static bool closest_generic(const bvh *b, const ray *r, hit *h) { return wide_query(b, r, h, false, BVH_SIMD, LEAVES_ANY); }
static bool any_spheres(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, LEAVES_SPHERES);
}
static bool any_triangles(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, LEAVES_TRIANGLES);
}
static bool any_generic(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, LEAVES_ANY);
}

bool bvh_intersect_scalar(const bvh *b, const ray *r, hit *h) { return wide_query(b, r, h, false, false, LEAVES_ANY); }

bool bvh_occluded_scalar(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, false, LEAVES_ANY);
}

bool bvh_intersect(const bvh *b, const ray *r, hit *h) {
    if (b->spheres_only) return closest_spheres(b, r, h);
    return b->triangles_only ? closest_triangles(b, r, h) : closest_generic(b, r, h);
}

bool bvh_occluded(const bvh *b, const ray *r) {
    if (b->spheres_only) return any_spheres(b, r);
    return b->triangles_only ? any_triangles(b, r) : any_generic(b, r);
}
