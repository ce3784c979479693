// bvh2_traverse.c — closest-hit and any-hit traversal of the binary BVH: nearest child first, a small stack,
// every primitive tested one at a time (the structure --accel bvh2 selects, and the reference layout).
#include "accel/bvh_prim.h"

// Entry distance of the ray into a binary node's box, or +inf when it misses within (tmin, tlimit].
static inline float box2_enter(const bvh2_node *n, const trav_ray *tr, float tlimit, bool ties) {
    float tn = tr->r->tmin, tf = INFINITY;
    for (int k = 0; k < 3; k++) {
        tn = max_sse(slab_t(n->box[tr->near[k]], tr->inv[k], tr->noi[k]), tn);
        tf = min_sse(slab_t(n->box[tr->far[k]], tr->inv[k], tr->noi[k]), tf);
    }
    tf = slab_exit(tf, tlimit, ties);
    return tn <= tf ? tn : INFINITY;
}

// One ray through the binary BVH b from its root, improving *best; true when anything was hit.
static bool bvh2_run(const bvh *b, const ray *r, hit *best, uint32_t inst_id, bool any) {
    if (!b->nodes2 || ray_is_nan(r)) return false;
    trav_ray tr = trav_setup(r);
    tri_cache tc = {.ready = false};
    stack_entry stack[BIN_STACK];
    int sp = 0;
    bool found = false;
    if (box2_enter(&b->nodes2[0], &tr, best->t, !any) == INFINITY) return false;
    uint32_t id = 0;
    for (;;) {
        const bvh2_node *n = &b->nodes2[id];
        if (n->count == 0) {
            uint32_t c0 = id + 1, c1 = n->offset;
            float t0 = box2_enter(&b->nodes2[c0], &tr, best->t, !any);
            float t1 = box2_enter(&b->nodes2[c1], &tr, best->t, !any);
            if (t0 != INFINITY && t1 != INFINITY) {
                if (t1 < t0) {
                    uint32_t tmp = c0; c0 = c1; c1 = tmp;
                    float tt = t0; t0 = t1; t1 = tt;
                }
                stack[sp++] = (stack_entry){c1, t1};
                id = c0;
                continue;
            }
            if (t0 != INFINITY) { id = c0; continue; }
            if (t1 != INFINITY) { id = c1; continue; }
        } else {
            for (uint32_t i = 0; i < n->count; i++) {
                prim_ref ref = b->refs[n->offset + i];
                if (!prim_hit(b, ref.kind, ref.index, prim_ref_instance(ref), r, &tc, best, inst_id, any, MODE_BINARY))
                    continue;
                found = true;
                if (any) return true;
            }
        }
        // Pop the nearest pending subtree that can still hold a nearer hit.
        for (;;) {
            if (sp == 0) return found;
            stack_entry e = stack[--sp];
            if (slab_keeps(e.t, best->t, any)) { id = e.ref; break; }
        }
    }
}

// An instance's BLAS (bvh_prim.h): a binary BVH too.
static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    (void)mode; // MODE_BINARY: the binary BVH enters only binary BLASes
    return bvh2_run(blas, r, best, inst_id, any);
}

bool bvh2_intersect(const bvh *b, const ray *r, hit *h) {
    hit best = bvh_no_hit(r);
    if (!bvh2_run(b, r, &best, HIT_NO_INSTANCE, false)) return false;
    *h = best;
    return true;
}

bool bvh2_occluded(const bvh *b, const ray *r) {
    hit best = bvh_no_hit(r);
    return bvh2_run(b, r, &best, HIT_NO_INSTANCE, true);
}
