// bvh_traverse.c — closest-hit and any-hit traversal of the wide BVH: nearest child first with a small
// stack, box tests of all eight children at once and sphere packets in one SIMD pass (bvh_simd.h), or the
// portable scalar path computing the same values; instances enter their mesh's BVH in object space.
#include "accel/bvh_kernel.h"

#if BVH_SIMD
#include "accel/bvh_simd.h"
#endif

/* ------------------------------------------------------------------------------------------------ */
/* Primitives tested one at a time                                                                    */

static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode);

/// What a BVH's leaves may hold, so that a traversal compiles only the tests it needs (a compile-time constant
/// after inlining): spheres only, triangles and quads only (both in triangle packets), or anything.
enum { LEAVES_SPHERES, LEAVES_TRIANGLES, LEAVES_ANY };

// An instance: the ray taken to object space by world_to_object (direction not normalised, so t keeps its
// meaning), then the mesh's BVH or the object-space sphere. True when it hit (any-hit queries stop there).
static bool instance_hit(const bvh *b, uint32_t index, const mat4 *world_to_object, const ray *r, hit *best, bool any,
                         trav_mode mode) {
    const instance *in = &b->instances[index];
    ray o = mat4_apply_ray(world_to_object, r);
    if (in->kind == INSTANCE_SPHERE) {
        const sphere *sp = &b->instance_spheres[in->index];
        float t;
        if (!sphere_intersect(sp->center, sp->radius, &o, o.tmin, o.tmax, &t)) return false;
        offer(best, (hit){t, in->index, HIT_SPHERE, index, 0.0f, 0.0f});
        return true;
    }
    return blas_traverse(&b->blas[in->index], &o, best, index, any, mode);
}

// A moving instance: its transform at the ray's time, then as any instance. Out of line: only scenes with
// motion reach it.
static __attribute__((noinline)) bool moving_instance_hit(const bvh *b, uint32_t index, const ray *r, hit *best,
                                                          bool any, trav_mode mode) {
    transform xf;
    motion_at(&b->motions[b->instances[index].motion - 1], r->time, &xf);
    return instance_hit(b, index, &xf.inv, r, best, any, mode);
}

// A moving sphere: the sphere where it is at the ray's time.
static __attribute__((noinline)) bool moving_sphere_hit(const bvh *b, uint32_t index, const ray *r, hit *best,
                                                        uint32_t inst_id) {
    vec3 c = moving_sphere_center(&b->moving_spheres[index], r->time);
    float t;
    if (!sphere_intersect(c, b->moving_spheres[index].radius, r, r->tmin, r->tmax, &t)) return false;
    offer(best, (hit){t, index, HIT_MOVING_SPHERE, inst_id, 0.0f, 0.0f});
    return true;
}

// One primitive that is not tested in SIMD: a quad, a triangle of b's mesh or of the flattened instance
// `owner` (else HIT_NO_INSTANCE), an instance (or a sphere in the binary BVH). `inst_id` is the instance whose
// mesh b is, or HIT_NO_INSTANCE. True when it hit.
static inline bool prim_hit(const bvh *b, uint32_t kind, uint32_t index, uint32_t owner, const ray *r, tri_cache *tc,
                            hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    switch ((prim_kind)kind) {
    case PRIM_SPHERE: {
        const sphere *s = &b->spheres[index];
        float t;
        if (!sphere_intersect(s->center, s->radius, r, r->tmin, r->tmax, &t)) return false;
        offer(best, (hit){t, index, HIT_SPHERE, inst_id, 0.0f, 0.0f});
        return true;
    }
    case PRIM_QUAD: {
        quad_hit qh;
        if (!quad_intersect(&b->quads[index], tri_for(tc, r), r->tmin, r->tmax, &qh)) return false;
        offer(best, (hit){qh.t, index, HIT_QUAD, inst_id, qh.alpha, qh.beta});
        return true;
    }
    case PRIM_TRIANGLE: {
        const mesh *m = owner == HIT_NO_INSTANCE ? b->mesh : b->flat[owner];
        tri_hit th;
        if (!mesh_intersect_triangle(m, index, tri_for(tc, r), r->tmin, r->tmax, &th)) return false;
        offer(best, (hit){th.t, index, HIT_TRIANGLE, owner == HIT_NO_INSTANCE ? inst_id : owner, th.b1, th.b2});
        return true;
    }
    case PRIM_INSTANCE: return instance_hit(b, index, &b->instances[index].xf.inv, r, best, any, mode);
    case PRIM_MOVING_SPHERE: return moving_sphere_hit(b, index, r, best, inst_id);
    case PRIM_MOVING_INSTANCE: return moving_instance_hit(b, index, r, best, any, mode);
    }
    return false;
}

// A packet of primitives tested one at a time (quads, triangles, instances), out of line so that the
// sphere path stays small enough to inline. Takes and returns the best hit by value: its address must
// not escape the traversal, or it could not stay in registers there. *hit_any says whether any was hit.
static __attribute__((noinline)) hit packet_hit(const bvh *b, const bvh_index_packet *p, const ray *r, tri_cache *tc,
                                                hit best, uint32_t inst_id, bool any, trav_mode mode, bool *hit_any) {
    *hit_any = false;
    for (uint32_t k = 0; k < p->h.count; k++) {
        if (!prim_hit(b, p->h.kind, p->prim[k], HIT_NO_INSTANCE, r, tc, &best, inst_id, any, mode)) continue;
        *hit_any = true;
        if (any) break;
    }
    return best;
}

// Offers the hit on lane k of triangle packet p: a triangle of the BVH's mesh or of the packet's flattened
// instance, or half of a quad (lanes 2j and 2j + 1 are quad prim[2j]). `inst_id` is the instance whose mesh
// the BVH is; at most one of it and the packet's instance is not HIT_NO_INSTANCE (the largest value).
static inline void offer_triangle(hit *best, const bvh_triangle_packet *p, int k, float t, float b1, float b2,
                                  uint32_t inst_id) {
    uint32_t id = p->h.instance < inst_id ? p->h.instance : inst_id;
    if (p->h.kind == PRIM_QUAD) {
        quad_hit qh = quad_hit_of(&(tri_hit){t, 1.0f - b1 - b2, b1, b2}, k & 1);
        offer(best, (hit){qh.t, p->prim[k], HIT_QUAD, id, qh.alpha, qh.beta});
    } else {
        offer(best, (hit){t, p->prim[k], HIT_TRIANGLE, id, b1, b2});
    }
}

// A packet of triangles one lane at a time, through tri_intersect: the scalar path, and the reference the
// SIMD test matches bit for bit. Out of line and by value, as packet_hit.
static __attribute__((noinline)) hit triangle_packet_scalar(const bvh_triangle_packet *p, const ray *r, tri_cache *tc,
                                                            hit best, uint32_t inst_id, bool any, bool *hit_any) {
    const tri_ray *tr = tri_for(tc, r);
    *hit_any = false;
    uint32_t lanes = p->h.kind == PRIM_QUAD ? 2 * p->h.count : p->h.count;
    for (uint32_t k = 0; k < lanes; k++) {
        vec3 v[3];
        for (int j = 0; j < 3; j++) v[j] = v3(p->v[j][0][k], p->v[j][1][k], p->v[j][2][k]);
        tri_hit th;
        if (!tri_intersect(tr, v[0], v[1], v[2], r->tmin, r->tmax, &th)) continue;
        *hit_any = true;
        if (any) break;
        offer_triangle(&best, p, (int)k, th.t, th.b1, th.b2, inst_id);
    }
    return best;
}

#if BVH_SIMD
// A packet of triangles in SIMD (triangles_simd), its hits offered lane by lane.
static __attribute__((noinline)) hit triangle_packet_simd(const bvh_triangle_packet *p, const ray *r, tri_cache *tc,
                                                          hit best, uint32_t inst_id, bool any, bool *hit_any) {
    _Alignas(32) float t[BVH_PACKET], b1[BVH_PACKET], b2[BVH_PACKET];
    simd_tri st;
    simd_tri_setup(tri_for(tc, r), r->tmin, r->tmax, &st);
    unsigned mask = triangles_simd(p, &st, t, b1, b2);
    *hit_any = mask != 0;
    if (!mask || any) return best;
    do {
        int k = __builtin_ctz(mask);
        mask &= mask - 1;
        offer_triangle(&best, p, k, t[k], b1[k], b2[k], inst_id);
    } while (mask);
    return best;
}
#else
#define triangle_packet_simd triangle_packet_scalar
#endif

bool bvh_prim_hit(const bvh *b, prim_ref ref, const ray *r, tri_cache *tc, hit *best, uint32_t inst_id, bool any,
                  trav_mode mode) {
    return prim_hit(b, ref.kind, ref.index, prim_ref_instance(ref), r, tc, best, inst_id, any, mode);
}

/* ------------------------------------------------------------------------------------------------ */
/* Wide BVH, scalar path                                                                              */

// Box tests of every child of a wide node; returns the mask of children the ray enters before
// tlimit, and their entry distances in tnear.
static inline unsigned wnode_test_scalar(const bvh_wnode *n, const trav_ray *tr, float tlimit, bool ties,
                                         float *tnear) {
    unsigned mask = 0;
    for (int i = 0; i < BVH_WIDTH; i++) {
        // The same values as the SIMD path: it takes both planes of a slab by min and max where this picks the
        // rows by the direction's signs (trav_setup), and keeps the order of the max/min operations below.
        float nx = slab_t(n->box[tr->near[0]][i], tr->inv[0], tr->noi[0]);
        float ny = slab_t(n->box[tr->near[1]][i], tr->inv[1], tr->noi[1]);
        float nz = slab_t(n->box[tr->near[2]][i], tr->inv[2], tr->noi[2]);
        float fx = slab_t(n->box[tr->far[0]][i], tr->inv[0], tr->noi[0]);
        float fy = slab_t(n->box[tr->far[1]][i], tr->inv[1], tr->noi[1]);
        float fz = slab_t(n->box[tr->far[2]][i], tr->inv[2], tr->noi[2]);
        // The slab distances as second operands: an empty slot's NaN reaches tn, and tn <= tf fails.
        float tn = max_sse(max_sse(tr->r->tmin, nx), max_sse(ny, nz));
        float tf = min_sse(min_sse(fx, fy), fz);
        tf = slab_exit(tf, tlimit, ties);
        tnear[i] = tn;
        if (tn <= tf) mask |= 1u << i;
    }
    return mask;
}

// Tests one leaf's packets one primitive at a time. True when something was hit.
static inline bool leaf_scalar(const bvh *b, uint32_t ref, const ray *r, tri_cache *tc, hit *best, uint32_t inst_id,
                               bool any, int leaves) {
    const bvh_slot *slot = &b->slots[ref & ~BVH_LEAF];
    bool found = false;
    for (;;) {
        const bvh_packet_header *hd = (const bvh_packet_header *)(const void *)slot;
        if (hd->kind == PRIM_SPHERE) {
            const bvh_sphere_packet *p = (const bvh_sphere_packet *)(const void *)slot;
            for (uint32_t k = 0; k < hd->count; k++) {
                float t;
                if (!sphere_intersect(v3(p->cx[k], p->cy[k], p->cz[k]), p->radius[k], r, r->tmin, r->tmax, &t))
                    continue;
                found = true;
                if (any) return true;
                offer(best, (hit){t, p->prim[k], HIT_SPHERE, inst_id, 0.0f, 0.0f});
            }
        } else if (leaves != LEAVES_SPHERES) {
            bool h;
            if (hd->kind == PRIM_TRIANGLE || hd->kind == PRIM_QUAD)
                *best = triangle_packet_scalar((const bvh_triangle_packet *)(const void *)slot, r, tc, *best, inst_id,
                                               any, &h);
            else
                *best = packet_hit(b, (const bvh_index_packet *)(const void *)slot, r, tc, *best, inst_id, any,
                                   MODE_WIDE_SCALAR, &h);
            if (h) {
                found = true;
                if (any) return true;
            }
        }
        if (hd->last) return found;
        slot += hd->slots;
    }
}

#if BVH_SIMD
// Tests one leaf: spheres and triangles in SIMD packets, everything else one at a time. True when something was hit.
// In a triangle-only BVH the triangle test is inlined here, the out-of-line calls (around which every vector
// register is saved) left out.
static inline __attribute__((always_inline)) bool leaf_simd(const bvh *b, uint32_t ref, const ray *r,
                                                            const simd_ray *s, const simd_tri *st, tri_cache *tc,
                                                            hit *best,
                                                            uint32_t inst_id, bool any, int leaves) {
    const bvh_slot *slot = &b->slots[ref & ~BVH_LEAF];
    bool found = false;
    for (;;) {
        const bvh_packet_header *hd = (const bvh_packet_header *)(const void *)slot;
        if (leaves == LEAVES_SPHERES || (leaves == LEAVES_ANY && hd->kind == PRIM_SPHERE)) {
            const bvh_sphere_packet *p = (const bvh_sphere_packet *)(const void *)slot;
            pk tv;
            unsigned mask = spheres_simd(p, s, &tv);
            if (mask) {
                found = true;
                if (any) return true;
                offer_spheres(best, p, mask, tv, inst_id);
            }
        } else if (leaves == LEAVES_TRIANGLES) {
            const bvh_triangle_packet *p = (const bvh_triangle_packet *)(const void *)slot;
            _Alignas(32) float t[BVH_PACKET], b1[BVH_PACKET], b2[BVH_PACKET];
            unsigned mask = triangles_simd(p, st, t, b1, b2);
            if (mask) {
                found = true;
                if (any) return true;
                float before = best->t;
                do {
                    int k = __builtin_ctz(mask);
                    mask &= mask - 1;
                    offer_triangle(best, p, k, t[k], b1[k], b2[k], inst_id);
                } while (mask);
                // A nearer triangle of a mesh: start fetching its record (corner indices, material), which
                // shading reads first, while the traversal goes on.
                if (best->t < before && p->h.kind == PRIM_TRIANGLE) {
                    const mesh *m = p->h.instance == HIT_NO_INSTANCE ? b->mesh : b->flat[p->h.instance];
                    if (m) _mm_prefetch((const char *)&m->triangles[best->prim], _MM_HINT_T0);
                }
            }
        } else {
            bool h;
            if (hd->kind == PRIM_TRIANGLE || hd->kind == PRIM_QUAD)
                *best = triangle_packet_simd((const bvh_triangle_packet *)(const void *)slot, r, tc, *best, inst_id,
                                             any, &h);
            else
                *best = packet_hit(b, (const bvh_index_packet *)(const void *)slot, r, tc, *best, inst_id, any,
                                   MODE_WIDE_SIMD, &h);
            if (h) {
                found = true;
                if (any) return true;
            }
        }
        if (hd->last) return found;
        slot += hd->slots;
    }
}
#else
typedef struct simd_ray simd_ray; // never defined: the SIMD path is not compiled in
typedef struct simd_tri simd_tri;
#endif

#if BVH_SIMD
// Starts fetching the children `mask` of node n in a tree of triangles: the nearest is read next, the others soon
// after, and on a large mesh nodes and leaves come from beyond the L2 cache.
static inline __attribute__((always_inline)) void prefetch_children(const bvh *b, const bvh_wnode *n, unsigned mask) {
    for (; mask; mask &= mask - 1) {
        uint32_t c = n->child[__builtin_ctz(mask)];
        const char *at = c & BVH_LEAF ? (const char *)&b->slots[c & ~BVH_LEAF] : (const char *)&b->wnodes[c];
        _mm_prefetch(at, _MM_HINT_T0);
        _mm_prefetch(at + 64, _MM_HINT_T0);
        _mm_prefetch(at + 128, _MM_HINT_T0);
        _mm_prefetch(at + 192, _MM_HINT_T0);
        if (c & BVH_LEAF) { // a triangle packet's corners run on to byte 319 (352 bytes, 32-aligned)
            _mm_prefetch(at + 256, _MM_HINT_T0);
            _mm_prefetch(at + 319, _MM_HINT_T0);
        }
    }
}
#endif

/* ------------------------------------------------------------------------------------------------ */
/* Wide traversal, shared by both paths (`simd` is a compile-time constant after inlining)           */

/// Where one ray's traversal stands: the next node or leaf and the depth of its stack.
typedef struct walk {
    uint32_t ref;
    int sp;
} walk;

enum { STEP_MORE, STEP_DONE, STEP_FOUND };

// One step of a traversal: visits w->ref (a node: choose the children to visit; a leaf: test it), then
// picks the next reference. STEP_DONE when nothing is left, STEP_FOUND when an any-hit query found one.
// The scalar path reads tr, the SIMD path sr; *found records whether anything was hit.
static inline __attribute__((always_inline)) int wide_step(const bvh *b, const ray *r, const trav_ray *tr,
                                                          const simd_ray *sr, const simd_tri *stri, tri_cache *tc,
                                                          stack_entry *stack,
                                                          walk *w, hit *best, uint32_t inst_id, bool *found,
                                                          bool any, bool simd, int leaves) {
#if !BVH_SIMD
    (void)sr;
    (void)stri;
    (void)simd;
#endif
    uint32_t ref = w->ref;
    if (!(ref & BVH_LEAF)) {
        const bvh_wnode *n = &b->wnodes[ref];
        float tnear[BVH_WIDTH];
        unsigned mask;
#if BVH_SIMD
        if (simd) mask = wnode_test_simd(n, sr, best->t, !any, tnear);
        else
#endif
            mask = wnode_test_scalar(n, tr, best->t, !any, tnear);
        if (mask != 0) {
#if BVH_SIMD
            // Start fetching every child the ray enters (prefetch_children).
            if (leaves == LEAVES_TRIANGLES) prefetch_children(b, n, mask);
#endif
            unsigned rest = mask & (mask - 1);
            if (rest == 0) {
                w->ref = n->child[__builtin_ctz(mask)];
                return STEP_MORE;
            }
            if (!any && (rest & (rest - 1)) == 0) {
                // Two children (the common case): descend into the nearer, push the farther.
                int i0 = __builtin_ctz(mask), i1 = __builtin_ctz(rest);
                bool swap = tnear[i1] < tnear[i0];
                uint32_t c0 = n->child[i0], c1 = n->child[i1];
                stack[w->sp].ref = swap ? c0 : c1;
                stack[w->sp].t = swap ? tnear[i0] : tnear[i1];
                w->sp++;
                w->ref = swap ? c1 : c0;
                return STEP_MORE;
            }
            // Push every child entered, sorted so that the nearest is on top, and descend into it.
            int base = w->sp, sp = w->sp;
            do {
                int i = __builtin_ctz(mask);
                mask &= mask - 1;
                stack_entry e = {n->child[i], tnear[i]};
                int j = sp++;
                if (!any)
                    while (j > base && stack[j - 1].t < e.t) {
                        stack[j] = stack[j - 1];
                        j--;
                    }
                stack[j] = e;
            } while (mask);
            w->ref = stack[--sp].ref;
            w->sp = sp;
            return STEP_MORE;
        }
    } else {
        bool hit_here;
#if BVH_SIMD
        if (simd) hit_here = leaf_simd(b, ref, r, sr, stri, tc, best, inst_id, any, leaves);
        else
#endif
            hit_here = leaf_scalar(b, ref, r, tc, best, inst_id, any, leaves);
        if (hit_here) {
            *found = true;
            if (any) return STEP_FOUND;
        }
    }
    // Pop the nearest pending subtree that can still hold a nearer hit.
    while (w->sp > 0) {
        stack_entry e = stack[--w->sp];
        if (slab_keeps(e.t, best->t, any)) {
            w->ref = e.ref;
            return STEP_MORE;
        }
    }
    return STEP_DONE;
}

// One ray through a wide BVH from its root, improving *best; true when anything was hit. With `leaves` not
// LEAVES_ANY, the code for other kinds, with its out-of-line calls (around which every vector register would
// have to be saved), is left out.
static inline __attribute__((always_inline)) bool wide_run(const bvh *b, const ray *r, hit *best, uint32_t inst_id,
                                                           bool any, bool simd, int leaves) {
    if (b->root == BVH_EMPTY && b->front == BVH_EMPTY) return false;
    trav_ray tr;
#if BVH_SIMD
    simd_ray sr;
    simd_tri stri;
    if (simd) {
        if (!simd_setup(r, &sr, leaves == LEAVES_TRIANGLES)) return false;
    } else
#endif
    {
        if (ray_is_nan(r)) return false;
        tr = trav_setup(r);
    }
    tri_cache tc = {.ready = false};
#if BVH_SIMD
    // A triangle-only BVH tests triangles in nearly every leaf: their constants are made once, up front.
    if (simd && leaves == LEAVES_TRIANGLES) {
        tri_for(&tc, r);
        simd_tri_setup(&tc.tr, r->tmin, r->tmax, &stri);
    }
#endif
    bool found = false;
#if BVH_SIMD
    // In a sphere-only BVH the huge spheres are one sphere packet. Its test does not depend on the tree's, so
    // a closest-hit query makes it first, where the processor overlaps it with the first tree steps, and
    // merges its hits after the tree (+1.3 to +1.6% on rtiow-final; docs/benchmarks.md).
    bool front_first = simd && !any && leaves == LEAVES_SPHERES && b->front != BVH_EMPTY;
    const bvh_sphere_packet *front = NULL;
    unsigned front_mask = 0;
    pk front_t = PK(setzero_ps)();
    if (front_first) {
        front = (const bvh_sphere_packet *)(const void *)&b->slots[b->front & ~BVH_LEAF];
        front_mask = spheres_simd(front, &sr, &front_t);
    }
#endif
    if (b->root != BVH_EMPTY) {
        stack_entry stack[WIDE_STACK];
        walk w = {b->root, 0};
#if BVH_SIMD
        int st;
        while ((st = wide_step(b, r, &tr, &sr, &stri, &tc, stack, &w, best, inst_id, &found, any, simd, leaves)) == STEP_MORE) {
        }
#else
        int st;
        while ((st = wide_step(b, r, &tr, NULL, NULL, &tc, stack, &w, best, inst_id, &found, any, simd, leaves)) == STEP_MORE) {
        }
#endif
        if (st == STEP_FOUND) return true;
    }
#if BVH_SIMD
    if (front_first) {
        if (front_mask) {
            found = true;
            offer_spheres(best, front, front_mask, front_t, inst_id);
        }
        return found;
    }
#endif
    // The huge spheres after the tree (bvh_build's split_front), against the tree's nearest hit.
    if (b->front != BVH_EMPTY) {
        bool h;
#if BVH_SIMD
        if (simd) h = leaf_simd(b, b->front, r, &sr, &stri, &tc, best, inst_id, any, leaves);
        else
#endif
            h = leaf_scalar(b, b->front, r, &tc, best, inst_id, any, leaves);
        found = found || h;
    }
    return found;
}

#if BVH_SIMD
/// One ray of a stream in flight: its registers' worth of setup, its best hit so far and where its walk stands.
typedef struct stream_ray {
    simd_ray sr;
    simd_tri stri;
    tri_cache tc;
    hit best;
    walk w;
    bool found;
} stream_ray;

// Readies ray r to walk b from its root with the SIMD kernels (`triangles`: b holds only triangle packets, whose
// constants are made up front); false for a NaN ray, which hits nothing.
static inline bool stream_ray_start(const bvh *b, const ray *r, stream_ray *q, bool triangles) {
    if (!simd_setup(r, &q->sr, triangles)) return false;
    q->tc.ready = false;
    if (triangles) {
        tri_for(&q->tc, r);
        simd_tri_setup(&q->tc.tr, r->tmin, r->tmax, &q->stri);
    }
    q->best = bvh_no_hit(r);
    q->w = (walk){b->root, 0};
    q->found = false;
    return true;
}

/// Deepest tree whose rays a stream traces all at once (deeper trees' go in smaller groups), and the stack entries a
/// ray of it may need.
enum { STREAM_DEPTH = 24, STREAM_STACK = STREAM_DEPTH * (BVH_WIDTH - 1) + 1 };

// wide_stream for a group of n rays whose stacks of `stride` entries fit in the group's room.
static inline __attribute__((always_inline)) void wide_stream_group(const bvh *b, int n, const ray *rays, hit *hits,
                                                                    bool *found, int leaves, size_t stride) {
    stream_ray s[BVH_STREAM];
    stack_entry stacks[BVH_STREAM * STREAM_STACK];
    int active[BVH_STREAM], live = 0;
    for (int i = 0; i < n; i++) {
        found[i] = false;
        // No tree, or a NaN ray: nothing to trace.
        if (b->root == BVH_EMPTY || !stream_ray_start(b, &rays[i], &s[i], leaves == LEAVES_TRIANGLES)) continue;
        active[live++] = i;
    }
    while (live > 0) {
        for (int k = 0; k < live;) {
            int i = active[k];
            stream_ray *q = &s[i];
            if (wide_step(b, &rays[i], NULL, &q->sr, &q->stri, &q->tc, &stacks[(size_t)i * stride], &q->w, &q->best,
                          HIT_NO_INSTANCE, &q->found, false, true, leaves) == STEP_MORE) {
                k++;
                continue;
            }
            found[i] = q->found;
            hits[i] = q->best;
            active[k] = active[--live]; // done: its place goes to the last ray in flight
        }
    }
}

// Closest hits of n <= BVH_STREAM rays through a wide BVH, one step of each ray in turn: a step ends by
// prefetching the children it will visit, so while one ray waits for memory the others work. Each ray makes the
// same steps in the same order as wide_run alone, so the hits are the same.
static inline __attribute__((always_inline)) void wide_stream(const bvh *b, int n, const ray *rays, hit *hits,
                                                              bool *found, int leaves) {
    // Each ray's stack holds at most BVH_WIDTH - 1 entries per level of the tree: packed that close, the stacks
    // in use share few cache lines. Room for STREAM_DEPTH levels keeps the frame small (a library's caller may
    // render on a thread with a small stack); a deeper tree's rays go in smaller groups.
    size_t stride = b->stats.depth < BVH_MAX_DEPTH ? (size_t)b->stats.depth * (BVH_WIDTH - 1) + 1 : WIDE_STACK;
    size_t group = BVH_STREAM * STREAM_STACK / stride;
    if (group > BVH_STREAM) group = BVH_STREAM;
    for (int first = 0; first < n; first += (int)group) {
        int count = n - first < (int)group ? n - first : (int)group;
        wide_stream_group(b, count, rays + first, hits + first, found + first, leaves, stride);
    }
}

/// A packet of coherent rays (directions of one sign per axis) bounded for box tests: the range of their origins
/// and of their inverse directions on each axis, broadcast.
typedef struct packet_bounds {
    __m256 olo[3], ohi[3], ilo[3], ihi[3];
    bool neg[3]; ///< the directions point down the axis: a box is entered by its upper plane
    float tmin;  ///< the smallest of the rays' tmin
} packet_bounds;

/// A packet's rays are set up and tested in groups of eight, the lanes of an AVX register.
enum { PACKET_GROUP = 8 };
_Static_assert(BVH_COHERENT % PACKET_GROUP == 0 && BVH_COHERENT <= 16, "whole groups, ray masks in an unsigned");

/// The triangle-test constants of a packet's rays, lane i for ray i: what tri_ray_make and simd_tri_setup make
/// for each ray alone, before the broadcasts (leaf_rays loads them as they are; leaf_each_ray broadcasts a lane).
typedef struct packet_rays {
    _Alignas(32) float ox[BVH_COHERENT], oy[BVH_COHERENT], oz[BVH_COHERENT]; ///< in ray-space order (x = kx, ...)
    _Alignas(32) float sx[BVH_COHERENT], sy[BVH_COHERENT], sz[BVH_COHERENT];
    _Alignas(32) float tmin[BVH_COHERENT], tmax[BVH_COHERENT];
    tri_ray tr[BVH_COHERENT]; ///< whole, for the lanes that take tri_intersect's double path
    bool uniform;             ///< every ray has the same kx, ky, kz: leaves can test all the rays at once (leaf_rays)
} packet_rays;

// Lane by lane, a where mask is set, else b.
static inline __m256 pick(__m256 mask, __m256 a, __m256 b) { return _mm256_blendv_ps(b, a, mask); }

// Readies rays[0, n) (0 < n <= BVH_COHERENT) in pr and pb: in each lane the operations simd_setup and
// tri_ray_make perform for that ray alone, so the same values, but six vector divisions for eight rays rather than
// forty-eight scalar ones, and no broadcast stored. Lanes past n repeat ray 0. False for a NaN ray (which hits
// nothing) or directions whose signs differ on some axis: then the rays go one by one.
static bool packet_setup(int n, const ray *rays, packet_rays *pr, packet_bounds *pb) {
    _Alignas(32) float o[3][BVH_COHERENT], d[3][BVH_COHERENT], inv[3][BVH_COHERENT];
    for (int i = 0; i < BVH_COHERENT; i++) {
        const ray *r = &rays[i < n ? i : 0];
        o[0][i] = r->o.x, o[1][i] = r->o.y, o[2][i] = r->o.z;
        d[0][i] = r->d.x, d[1][i] = r->d.y, d[2][i] = r->d.z;
        pr->tmin[i] = r->tmin;
        pr->tmax[i] = r->tmax;
    }
    const __m256 sign = _mm256_set1_ps(-0.0f), eps = _mm256_set1_ps(DIR_EPSILON), one = _mm256_set1_ps(1.0f),
                 zero = _mm256_setzero_ps();
    // Bit i of each: ray i has a NaN; a negative direction on axis a; z is its x axis, its y axis; x and y swapped.
    unsigned nan = 0, neg[3] = {0, 0, 0}, xf = 0, yf = 0, fl = 0;
    for (int g = 0; g < BVH_COHERENT; g += PACKET_GROUP) {
        __m256 ov[3], dv[3], nanv = zero;
        for (int a = 0; a < 3; a++) {
            ov[a] = _mm256_load_ps(&o[a][g]);
            dv[a] = _mm256_load_ps(&d[a][g]);
            nanv = _mm256_or_ps(nanv, _mm256_or_ps(_mm256_cmp_ps(ov[a], ov[a], _CMP_UNORD_Q),
                                                   _mm256_cmp_ps(dv[a], dv[a], _CMP_UNORD_Q)));
            // The box tests' inverse direction, a component too small for it made +-DIR_EPSILON (simd_setup).
            __m256 tiny = _mm256_cmp_ps(_mm256_andnot_ps(sign, dv[a]), eps, _CMP_LT_OQ);
            __m256 iv = _mm256_div_ps(one, pick(tiny, _mm256_or_ps(_mm256_and_ps(sign, dv[a]), eps), dv[a]));
            _mm256_store_ps(&inv[a][g], iv);
            neg[a] |= (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(iv, zero, _CMP_LT_OQ)) << g;
        }
        nan |= (unsigned)_mm256_movemask_ps(nanv) << g;
        // tri_ray_make in every lane: z the axis of the largest |d| (x before y before z on ties, as there), x and
        // y the next two cyclically, swapped when d.z < 0.
        __m256 ax = _mm256_andnot_ps(sign, dv[0]), ay = _mm256_andnot_ps(sign, dv[1]),
               az = _mm256_andnot_ps(sign, dv[2]);
        __m256 x_over_y = _mm256_cmp_ps(ax, ay, _CMP_GT_OQ);
        __m256 x_first = _mm256_and_ps(x_over_y, _mm256_cmp_ps(ax, az, _CMP_GT_OQ));
        __m256 y_first = _mm256_andnot_ps(x_over_y, _mm256_cmp_ps(ay, az, _CMP_GT_OQ));
        // Per lane, the component on axis kz and on the two after it (kz + 1 and kz + 2, cyclically).
        __m256 dz = pick(x_first, dv[0], pick(y_first, dv[1], dv[2]));
        __m256 d1 = pick(x_first, dv[1], pick(y_first, dv[2], dv[0]));
        __m256 d2 = pick(x_first, dv[2], pick(y_first, dv[0], dv[1]));
        __m256 o1 = pick(x_first, ov[1], pick(y_first, ov[2], ov[0]));
        __m256 o2 = pick(x_first, ov[2], pick(y_first, ov[0], ov[1]));
        __m256 flip = _mm256_cmp_ps(dz, zero, _CMP_LT_OQ);
        _mm256_store_ps(&pr->sx[g], _mm256_div_ps(pick(flip, d2, d1), dz));
        _mm256_store_ps(&pr->sy[g], _mm256_div_ps(pick(flip, d1, d2), dz));
        _mm256_store_ps(&pr->sz[g], _mm256_div_ps(one, dz));
        _mm256_store_ps(&pr->ox[g], pick(flip, o2, o1));
        _mm256_store_ps(&pr->oy[g], pick(flip, o1, o2));
        _mm256_store_ps(&pr->oz[g], pick(x_first, ov[0], pick(y_first, ov[1], ov[2])));
        xf |= (unsigned)_mm256_movemask_ps(x_first) << g;
        yf |= (unsigned)_mm256_movemask_ps(y_first) << g;
        fl |= (unsigned)_mm256_movemask_ps(flip) << g;
    }
    const unsigned all = (1u << BVH_COHERENT) - 1u;
    if (nan != 0) return false;
    for (int a = 0; a < 3; a++) {
        if (neg[a] != 0 && neg[a] != all) return false;
        pb->neg[a] = neg[a] != 0;
    }
    pr->uniform = (xf == 0 || xf == all) && (yf == 0 || yf == all) && (fl == 0 || fl == all);
    for (int i = 0; i < n; i++) {
        int kz = xf >> i & 1u ? 0 : yf >> i & 1u ? 1 : 2, k1 = kz == 2 ? 0 : kz + 1, k2 = kz == 0 ? 2 : kz - 1;
        bool f = fl >> i & 1u;
        pr->tr[i] = (tri_ray){rays[i].o, f ? k2 : k1, f ? k1 : k2, kz, pr->sx[i], pr->sy[i], pr->sz[i]};
    }
    // The range of origins and inverse directions, ray by ray in order.
    float olo[3], ohi[3], ilo[3], ihi[3];
    pb->tmin = rays[0].tmin;
    for (int a = 0; a < 3; a++) {
        olo[a] = ohi[a] = o[a][0];
        ilo[a] = ihi[a] = inv[a][0];
    }
    for (int i = 1; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            olo[a] = o[a][i] < olo[a] ? o[a][i] : olo[a];
            ohi[a] = o[a][i] > ohi[a] ? o[a][i] : ohi[a];
            ilo[a] = inv[a][i] < ilo[a] ? inv[a][i] : ilo[a];
            ihi[a] = inv[a][i] > ihi[a] ? inv[a][i] : ihi[a];
        }
        pb->tmin = rays[i].tmin < pb->tmin ? rays[i].tmin : pb->tmin;
    }
    for (int a = 0; a < 3; a++) {
        pb->olo[a] = _mm256_set1_ps(olo[a]);
        pb->ohi[a] = _mm256_set1_ps(ohi[a]);
        pb->ilo[a] = _mm256_set1_ps(ilo[a]);
        pb->ihi[a] = _mm256_set1_ps(ihi[a]);
    }
    return true;
}

// Interval product bounds: the least and greatest (b - o) inv over o in [olo, ohi], inv in [ilo, ihi].
static inline __m256 ia_min(__m256 b, __m256 olo, __m256 ohi, __m256 ilo, __m256 ihi) {
    __m256 dlo = _mm256_sub_ps(b, ohi), dhi = _mm256_sub_ps(b, olo);
    return _mm256_min_ps(_mm256_min_ps(_mm256_mul_ps(dlo, ilo), _mm256_mul_ps(dlo, ihi)),
                         _mm256_min_ps(_mm256_mul_ps(dhi, ilo), _mm256_mul_ps(dhi, ihi)));
}
static inline __m256 ia_max(__m256 b, __m256 olo, __m256 ohi, __m256 ilo, __m256 ihi) {
    __m256 dlo = _mm256_sub_ps(b, ohi), dhi = _mm256_sub_ps(b, olo);
    return _mm256_max_ps(_mm256_max_ps(_mm256_mul_ps(dlo, ilo), _mm256_mul_ps(dlo, ihi)),
                         _mm256_max_ps(_mm256_mul_ps(dhi, ilo), _mm256_mul_ps(dhi, ihi)));
}

// The children of n that some ray of the packet may enter before tlimit, by interval arithmetic, and a lower bound
// of where any of them enters each (tnear). Widened by 2^-18 of t each way: more than the rounding of these
// products and of the rays' own slab tests, so that no child a ray enters is missed (the boxes' padding covers
// the absolute errors).
static inline unsigned packet_node_test(const bvh_wnode *n, const packet_bounds *pb, float tlimit, float *tnear) {
    __m256 tn = _mm256_set1_ps(pb->tmin), tf = _mm256_set1_ps(INFINITY);
    for (int a = 0; a < 3; a++) {
        __m256 lo = _mm256_load_ps(n->box[a]), hi = _mm256_load_ps(n->box[3 + a]);
        __m256 enter = pb->neg[a] ? hi : lo, leave = pb->neg[a] ? lo : hi;
        tn = _mm256_max_ps(tn, ia_min(enter, pb->olo[a], pb->ohi[a], pb->ilo[a], pb->ihi[a]));
        tf = _mm256_min_ps(tf, ia_max(leave, pb->olo[a], pb->ohi[a], pb->ilo[a], pb->ihi[a]));
    }
    const __m256 margin = _mm256_set1_ps(0x1p-18f), sign = _mm256_set1_ps(-0.0f);
    tn = _mm256_sub_ps(tn, _mm256_mul_ps(_mm256_andnot_ps(sign, tn), margin));
    tf = _mm256_add_ps(tf, _mm256_mul_ps(_mm256_andnot_ps(sign, tf), margin));
    tf = _mm256_min_ps(tf, _mm256_set1_ps(tlimit));
    // Empty slots have NaN boxes: unordered, never entered.
    __m256 slot = _mm256_cmp_ps(_mm256_load_ps(n->box[0]), _mm256_load_ps(n->box[0]), _CMP_ORD_Q);
    _mm256_storeu_ps(tnear, tn);
    return (unsigned)_mm256_movemask_ps(_mm256_and_ps(slot, _mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
}

// Rays g + l of a packet against triangle k of packet p in tri_intersect itself, for each l in `lanes` (where
// leaf_rays found an edge function of zero), the result written into lane l of t, b1, b2. Returns the lanes hit.
static __attribute__((noinline)) unsigned rays_exact(const bvh_triangle_packet *p, int k, const packet_rays *pr, int g,
                                                     unsigned lanes, float *t, float *b1, float *b2) {
    vec3 v[3];
    for (int j = 0; j < 3; j++) v[j] = v3(p->v[j][0][k], p->v[j][1][k], p->v[j][2][k]);
    unsigned found = 0;
    do {
        int l = __builtin_ctz(lanes), i = g + l;
        lanes &= lanes - 1;
        if (exact_lane(&pr->tr[i], v[0], v[1], v[2], pr->tmin[i], pr->tmax[i], l, t, b1, b2)) found |= 1u << l;
    } while (lanes);
    return found;
}

// Leaf `ref` tested by the packet's rays in `lanes` (all of the same kx, ky, kz) at once, one triangle at a time
// against every ray: each lane computes exactly what triangles_simd computes for its ray (the same operations on
// the same values), so each ray finds the hits its own leaf test finds. A leaf of fewer triangles than rays
// (the ground quad's two) costs fewer tests than the rays one by one. Sets hit_any[i] where ray i hit something.
static void leaf_rays(const bvh *b, uint32_t ref, const packet_rays *pr, unsigned lanes, hit *best, bool *hit_any) {
    const int kx = pr->tr[0].kx, ky = pr->tr[0].ky, kz = pr->tr[0].kz;
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const bvh_slot *slot = &b->slots[ref & ~BVH_LEAF];
    for (;;) {
        const bvh_triangle_packet *p = (const bvh_triangle_packet *)(const void *)slot;
        int count = (int)(p->h.kind == PRIM_QUAD ? 2 * p->h.count : p->h.count); // a quad is two lanes
        const mesh *m = p->h.kind != PRIM_TRIANGLE           ? NULL
                        : p->h.instance == HIT_NO_INSTANCE ? b->mesh
                                                           : b->flat[p->h.instance];
        for (int k = 0; k < count; k++) {
            __m256 vx[3], vy[3], vz[3];
            for (int j = 0; j < 3; j++) {
                vx[j] = _mm256_set1_ps(p->v[j][kx][k]);
                vy[j] = _mm256_set1_ps(p->v[j][ky][k]);
                vz[j] = _mm256_set1_ps(p->v[j][kz][k]);
            }
            for (int g = 0; g < BVH_COHERENT; g += PACKET_GROUP) {
                unsigned group = lanes >> g & ((1u << PACKET_GROUP) - 1u);
                if (!group) continue;
                const __m256 ox = _mm256_load_ps(&pr->ox[g]), oy = _mm256_load_ps(&pr->oy[g]),
                             oz = _mm256_load_ps(&pr->oz[g]);
                const __m256 sx = _mm256_load_ps(&pr->sx[g]), sy = _mm256_load_ps(&pr->sy[g]);
                __m256 x[3], y[3], z[3];
                for (int j = 0; j < 3; j++) { // as triangles_simd: vertex j - o, sheared
                    z[j] = _mm256_sub_ps(vz[j], oz);
                    x[j] = _mm256_sub_ps(_mm256_sub_ps(vx[j], ox), _mm256_mul_ps(sx, z[j]));
                    y[j] = _mm256_sub_ps(_mm256_sub_ps(vy[j], oy), _mm256_mul_ps(sy, z[j]));
                }
                __m256 u = _mm256_sub_ps(_mm256_mul_ps(x[2], y[1]), _mm256_mul_ps(y[2], x[1]));
                __m256 v = _mm256_sub_ps(_mm256_mul_ps(x[0], y[2]), _mm256_mul_ps(y[0], x[2]));
                __m256 w = _mm256_sub_ps(_mm256_mul_ps(x[1], y[0]), _mm256_mul_ps(y[1], x[0]));
                __m256 neg = _mm256_or_ps(
                    _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_LT_OQ), _mm256_cmp_ps(v, zero, _CMP_LT_OQ)),
                    _mm256_cmp_ps(w, zero, _CMP_LT_OQ));
                __m256 pos = _mm256_or_ps(
                    _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_GT_OQ), _mm256_cmp_ps(v, zero, _CMP_GT_OQ)),
                    _mm256_cmp_ps(w, zero, _CMP_GT_OQ));
                __m256 zeros = _mm256_or_ps(
                    _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_EQ_OQ), _mm256_cmp_ps(v, zero, _CMP_EQ_OQ)),
                    _mm256_cmp_ps(w, zero, _CMP_EQ_OQ));
                unsigned exact = (unsigned)_mm256_movemask_ps(zeros) & group;
                unsigned inside = ~(unsigned)_mm256_movemask_ps(_mm256_and_ps(neg, pos)) & group & ~exact;
                if (!(inside | exact)) continue; // the common case: the triangle misses every ray of the group
                _Alignas(32) float t[PACKET_GROUP], b1[PACKET_GROUP], b2[PACKET_GROUP];
                unsigned mask = 0;
                if (inside) {
                    __m256 det = _mm256_add_ps(_mm256_add_ps(u, v), w);
                    __m256 dot = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(u, z[0]), _mm256_mul_ps(v, z[1])),
                                               _mm256_mul_ps(w, z[2]));
                    __m256 scaled = _mm256_mul_ps(dot, _mm256_load_ps(&pr->sz[g]));
                    __m256 inv = _mm256_div_ps(one, det);
                    __m256 tv = _mm256_mul_ps(scaled, inv);
                    __m256 in_range = _mm256_and_ps(_mm256_cmp_ps(tv, _mm256_load_ps(&pr->tmin[g]), _CMP_GT_OQ),
                                                    _mm256_cmp_ps(tv, _mm256_load_ps(&pr->tmax[g]), _CMP_LT_OQ));
                    __m256 ok = _mm256_and_ps(_mm256_cmp_ps(det, zero, _CMP_NEQ_OQ), in_range);
                    mask = inside & (unsigned)_mm256_movemask_ps(ok);
                    if (mask) {
                        _mm256_store_ps(t, tv);
                        _mm256_store_ps(b1, _mm256_mul_ps(v, inv));
                        _mm256_store_ps(b2, _mm256_mul_ps(w, inv));
                    }
                }
                if (exact) mask |= rays_exact(p, k, pr, g, exact, t, b1, b2);
                while (mask) {
                    int l = __builtin_ctz(mask), i = g + l;
                    mask &= mask - 1;
                    hit_any[i] = true;
                    float before = best[i].t;
                    offer_triangle(&best[i], p, k, t[l], b1[l], b2[l], HIT_NO_INSTANCE);
                    // A nearer triangle of a mesh: fetch its record for shading, as leaf_simd does.
                    if (m && best[i].t < before) _mm_prefetch((const char *)&m->triangles[best[i].prim], _MM_HINT_T0);
                }
            }
        }
        if (p->h.last) return;
        slot += p->h.slots;
    }
}

// Leaf `ref` tested by the packet's rays in `lanes` one by one (rays of different ray-space axes), each with its
// own leaf test, its constants broadcast from their lanes.
static void leaf_each_ray(const bvh *b, uint32_t ref, const ray *rays, const packet_rays *pr, unsigned lanes, hit *best,
                          bool *hit_any) {
    do {
        int i = __builtin_ctz(lanes);
        lanes &= lanes - 1;
        const tri_ray *tr = &pr->tr[i];
        simd_tri st = {PK(set1_ps)(pr->ox[i]), PK(set1_ps)(pr->oy[i]), PK(set1_ps)(pr->oz[i]),
                       PK(set1_ps)(pr->sx[i]), PK(set1_ps)(pr->sy[i]), PK(set1_ps)(pr->sz[i]),
                       PK(set1_ps)(pr->tmin[i]), PK(set1_ps)(pr->tmax[i]), tr->kx, tr->ky, tr->kz,
                       pr->tmin[i], pr->tmax[i], tr};
        tri_cache unused = {.ready = false};
        if (leaf_simd(b, ref, &rays[i], NULL, &st, &unused, &best[i], HIT_NO_INSTANCE, false, LEAVES_TRIANGLES))
            hit_any[i] = true;
    } while (lanes);
}

// Closest hits of n <= BVH_COHERENT rays through a tree of triangles, traversed together: one interval test of
// a node for the whole packet, each leaf tested by every ray that may still find a nearer hit there. A ray tests
// every leaf its own traversal would have reached (and maybe more), and bvh_better keeps the same hit whatever the
// order: the hits are those of bvh_intersect.
static void coherent_run(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    packet_rays pr;
    packet_bounds pb;
    if (b->root == BVH_EMPTY || n <= 0 || !packet_setup(n, rays, &pr, &pb)) {
        for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
        return;
    }
    hit best[BVH_COHERENT];
    bool hit_any[BVH_COHERENT];
    float tlimit = 0.0f; // the farthest of the rays' best hits: beyond it no ray can gain
    for (int i = 0; i < n; i++) {
        best[i] = bvh_no_hit(&rays[i]);
        hit_any[i] = false;
        tlimit = best[i].t > tlimit ? best[i].t : tlimit;
    }
    stack_entry stack[WIDE_STACK];
    int sp = 0;
    uint32_t ref = b->root;
    float ref_t = pb.tmin;
    for (;;) {
        if (!(ref & BVH_LEAF)) {
            const bvh_wnode *node = &b->wnodes[ref];
            float tnear[BVH_WIDTH];
            unsigned mask = packet_node_test(node, &pb, tlimit, tnear);
            if (mask != 0) {
                prefetch_children(b, node, mask); // every child some ray enters
                // Push every child entered, the nearest on top, and descend into it.
                int base = sp;
                do {
                    int i = __builtin_ctz(mask);
                    mask &= mask - 1;
                    stack_entry e = {node->child[i], tnear[i]};
                    int j = sp++;
                    while (j > base && stack[j - 1].t < e.t) {
                        stack[j] = stack[j - 1];
                        j--;
                    }
                    stack[j] = e;
                } while (mask);
                sp--;
                ref = stack[sp].ref;
                ref_t = stack[sp].t;
                continue;
            }
        } else {
            // A ray whose hit lies before any ray enters the leaf has nothing to find there.
            unsigned lanes = 0;
            for (int i = 0; i < n; i++) lanes |= (unsigned)!(best[i].t < ref_t) << i;
            if (lanes && pr.uniform) leaf_rays(b, ref, &pr, lanes, best, hit_any);
            else if (lanes) leaf_each_ray(b, ref, rays, &pr, lanes, best, hit_any);
            tlimit = 0.0f;
            for (int i = 0; i < n; i++) tlimit = best[i].t > tlimit ? best[i].t : tlimit;
        }
        // The nearest pending subtree that a ray can still gain from.
        while (sp > 0 && stack[sp - 1].t > tlimit) sp--;
        if (sp == 0) break;
        sp--;
        ref = stack[sp].ref;
        ref_t = stack[sp].t;
    }
    for (int i = 0; i < n; i++) {
        found[i] = hit_any[i];
        hits[i] = best[i];
    }
}

bool bvh_coherent(const bvh *b) { return b->triangles_only && b->front == BVH_EMPTY; }

void bvh_intersect_coherent(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    if (bvh_coherent(b)) coherent_run(b, n, rays, hits, found);
    else
        for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
}

bool bvh_streams(const bvh *b) { return !b->spheres_only && b->front == BVH_EMPTY; }

void bvh_intersect_stream(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    if (!bvh_streams(b)) { // the sphere traversal is tuned for one ray; huge spheres are tested after the tree
        for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
    } else if (b->triangles_only) {
        wide_stream(b, n, rays, hits, found, LEAVES_TRIANGLES);
    } else {
        wide_stream(b, n, rays, hits, found, LEAVES_ANY);
    }
}
#else
bool bvh_streams(const bvh *b) {
    (void)b;
    return false;
}

void bvh_intersect_stream(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
}

bool bvh_coherent(const bvh *b) {
    (void)b;
    return false;
}

void bvh_intersect_coherent(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
}
#endif

static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    switch (mode) {
    case MODE_WIDE_SIMD: // a mesh's BVH holds only triangles
        if (blas->triangles_only) return wide_run(blas, r, best, inst_id, any, BVH_SIMD, LEAVES_TRIANGLES);
        return wide_run(blas, r, best, inst_id, any, BVH_SIMD, LEAVES_ANY);
    case MODE_WIDE_SCALAR: return wide_run(blas, r, best, inst_id, any, false, LEAVES_ANY);
    case MODE_BINARY: return bvh2_run(blas, r, best, inst_id, any);
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
