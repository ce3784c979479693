// bvh_wide.h — the wide BVH's traversal step, shared by the single-ray (bvh_traverse.c), stream (bvh_stream.c)
// and packet (bvh_packet.c) traversals (private to them): the box tests of a node's eight children, the leaf tests,
// wide_step, one step of one ray, and wide_run, one ray from the root, written once for both instruction sets;
// its out-of-line leaf test, which enters instances, in bvh_wide.c. The per-instruction-set kernels are
// whole functions: with AVX2 and FMA (BVH_SIMD) those of bvh_simd.h and the SIMD leaf below; without, stand-ins of
// the same names that run the scalar kernels, so that no function body holds an #if (`simd` is a compile-time
// constant after inlining, and the stand-ins are never reached where it is 0).
#ifndef GLINT_BVH_WIDE_H
#define GLINT_BVH_WIDE_H

#include "accel/bvh_kernel.h"

#if BVH_SIMD
#include "accel/bvh_simd.h"
#endif

/// What a BVH's leaves may hold, so that a traversal compiles only the tests it needs (a compile-time constant
/// after inlining): spheres only, triangles and quads only (both in triangle packets), or anything.
enum { LEAVES_SPHERES, LEAVES_TRIANGLES, LEAVES_ANY };

/// A packet of primitives tested one at a time (quads, triangles, instances), out of line so that the sphere path
/// stays small enough to inline (bvh_wide.c: it enters instances, hence the wide traversal). Takes and returns
/// the best hit by value: its address must not escape the traversal, or it could not stay in registers there.
/// *hit_any says whether any was hit.
hit bvh_packet_hit(const bvh *b, const bvh_index_packet *p, const ray *r, tri_cache *tc, hit best, uint32_t inst_id,
                   bool any, trav_mode mode, bool *hit_any);

/// Offers the hit on lane k of triangle packet p: a triangle of the BVH's mesh or of the packet's flattened
/// instance, or half of a quad (lanes 2j and 2j + 1 are quad prim[2j]). `inst_id` is the instance whose mesh
/// the BVH is; at most one of it and the packet's instance is not HIT_NO_INSTANCE (the largest value).
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

/// A packet of triangles one lane at a time, through tri_intersect: the scalar path, and the reference the
/// SIMD test matches bit for bit. Out of line and by value, as bvh_packet_hit (`unused`: a file may not need it).
static __attribute__((noinline, unused)) hit triangle_packet_scalar(const bvh_triangle_packet *p, const ray *r,
                                                                    tri_cache *tc, hit best, uint32_t inst_id,
                                                                    bool any, bool *hit_any) {
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


/// Box tests of every child of a wide node; returns the mask of children the ray enters before
/// tlimit, and their entry distances in tnear.
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

/// Tests one leaf's packets one primitive at a time. True when something was hit.
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
                *best = bvh_packet_hit(b, (const bvh_index_packet *)(const void *)slot, r, tc, *best, inst_id, any,
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
/// A packet of triangles in SIMD (triangles_simd) in a leaf of mixed kinds: the lanes hit, their t and barycentrics
/// in the caller's arrays, for the caller to offer. Out of line (the sphere path around it stays small), it sets
/// up the ray's triangle constants in *st on the ray's first triangle packet (st->tr NULL until then) and keeps
/// them for the next: a ray through a mixed tree meets several.
static __attribute__((noinline, unused)) unsigned triangle_packet_lanes(const bvh_triangle_packet *p, const ray *r,
                                                                        tri_cache *tc, simd_tri *st, float *t,
                                                                        float *b1, float *b2) {
    if (!st->tr) simd_tri_setup(tri_for(tc, r), r->tmin, r->tmax, st);
    return triangles_simd(p, st, t, b1, b2);
}

/// Tests one leaf: spheres and triangles in SIMD packets, everything else one at a time. True when something was hit.
/// In a triangle-only BVH the triangle test is inlined here, the out-of-line calls (around which every vector
/// register is saved) left out.
static inline __attribute__((always_inline)) bool leaf_simd(const bvh *b, uint32_t ref, const ray *r,
                                                            const simd_ray *s, simd_tri *st, tri_cache *tc,
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
                    const mesh *m = p->h.instance == HIT_NO_INSTANCE ? b->input.mesh : b->input.flat[p->h.instance];
                    if (m) _mm_prefetch((const char *)&m->triangles[best->prim], _MM_HINT_T0);
                }
            }
        } else if (hd->kind == PRIM_TRIANGLE || hd->kind == PRIM_QUAD) {
            const bvh_triangle_packet *p = (const bvh_triangle_packet *)(const void *)slot;
            _Alignas(32) float t[BVH_PACKET], b1[BVH_PACKET], b2[BVH_PACKET];
            unsigned mask = triangle_packet_lanes(p, r, tc, st, t, b1, b2);
            if (mask) {
                found = true;
                if (any) return true;
                do {
                    int k = __builtin_ctz(mask);
                    mask &= mask - 1;
                    offer_triangle(best, p, k, t[k], b1[k], b2[k], inst_id);
                } while (mask);
            }
        } else {
            bool h;
            *best = bvh_packet_hit(b, (const bvh_index_packet *)(const void *)slot, r, tc, *best, inst_id, any,
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

/// Starts fetching the children `mask` of node n in a tree of triangles: the nearest is read next, the others soon
/// after, and on a large mesh nodes and leaves come from beyond the L2 cache.
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

/// The huge spheres of a sphere-only BVH tested before the tree (wide_run): their packet, the lanes hit, where.
typedef struct front_spheres {
    const bvh_sphere_packet *p;
    unsigned mask;
    pk t;
} front_spheres;

/// Tests b's huge spheres (one sphere packet) for the ray in sr, before the tree.
static inline __attribute__((always_inline)) void front_spheres_test(const bvh *b, const simd_ray *sr,
                                                                     front_spheres *f) {
    f->p = (const bvh_sphere_packet *)(const void *)&b->slots[b->front & ~BVH_LEAF];
    f->mask = spheres_simd(f->p, sr, &f->t);
}

/// Offers the hits front_spheres_test found, after the tree; true when there was one.
static inline __attribute__((always_inline)) bool front_spheres_offer(const front_spheres *f, hit *best,
                                                                      uint32_t inst_id) {
    if (!f->mask) return false;
    offer_spheres(best, f->p, f->mask, f->t, inst_id);
    return true;
}
#else
// Without AVX2 and FMA: the SIMD kernels' stand-ins, the scalar kernels under their names.

/// The ray as the stand-in kernels take it: prepared for the scalar box tests.
typedef struct simd_ray {
    trav_ray tr;
} simd_ray;

/// The triangle-test constants in registers: none without SIMD (the tri_cache holds them); `tr` as the SIMD one has
/// it, set and never read.
typedef struct simd_tri {
    const tri_ray *tr;
} simd_tri;

/// The huge spheres tested before the tree: never without SIMD (they are tested after it, as a leaf).
typedef struct front_spheres {
    char unused;
} front_spheres;

/// trav_setup under simd_setup's name; false for a NaN ray.
static inline bool simd_setup(const ray *r, simd_ray *s, bool boxes_only) {
    (void)boxes_only;
    if (ray_is_nan(r)) return false;
    s->tr = trav_setup(r);
    return true;
}

/// Nothing to set up: the scalar triangle test reads the tri_cache.
static inline void simd_tri_setup(const tri_ray *tr, float tmin, float tmax, simd_tri *st) {
    (void)tr;
    (void)tmin;
    (void)tmax;
    (void)st;
}

/// The scalar box tests under wnode_test_simd's name.
static inline unsigned wnode_test_simd(const bvh_wnode *n, const simd_ray *s, float tlimit, bool ties, float *tnear) {
    return wnode_test_scalar(n, &s->tr, tlimit, ties, tnear);
}

/// The scalar leaf test under leaf_simd's name.
static inline bool leaf_simd(const bvh *b, uint32_t ref, const ray *r, const simd_ray *s, simd_tri *st,
                             tri_cache *tc, hit *best, uint32_t inst_id, bool any, int leaves) {
    (void)s;
    (void)st;
    return leaf_scalar(b, ref, r, tc, best, inst_id, any, leaves);
}

/// No prefetch without SIMD.
static inline void prefetch_children(const bvh *b, const bvh_wnode *n, unsigned mask) {
    (void)b;
    (void)n;
    (void)mask;
}

/// Never called without SIMD (wide_run tests the huge spheres after the tree).
static inline void front_spheres_test(const bvh *b, const simd_ray *sr, front_spheres *f) {
    (void)b;
    (void)sr;
    (void)f;
}

/// Never called without SIMD: no hit.
static inline bool front_spheres_offer(const front_spheres *f, hit *best, uint32_t inst_id) {
    (void)f;
    (void)best;
    (void)inst_id;
    return false;
}
#endif

/* ------------------------------------------------------------------------------------------------ */
/* One step of the wide traversal, shared by both paths (`simd` is a compile-time constant after inlining) */

/// Where one ray's traversal stands: the next node or leaf and the depth of its stack.
typedef struct walk {
    uint32_t ref;
    int sp;
} walk;

enum { STEP_MORE, STEP_DONE, STEP_FOUND };

/// One step of a traversal: visits w->ref (a node: choose the children to visit; a leaf: test it), then
/// picks the next reference. STEP_DONE when nothing is left, STEP_FOUND when an any-hit query found one.
/// The scalar path reads tr, the SIMD path sr; *found records whether anything was hit.
static inline __attribute__((always_inline)) int wide_step(const bvh *b, const ray *r, const trav_ray *tr,
                                                          const simd_ray *sr, simd_tri *stri, tri_cache *tc,
                                                          stack_entry *stack,
                                                          walk *w, hit *best, uint32_t inst_id, bool *found,
                                                          bool any, bool simd, int leaves) {
    uint32_t ref = w->ref;
    if (!(ref & BVH_LEAF)) {
        const bvh_wnode *n = &b->wnodes[ref];
        float tnear[BVH_WIDTH];
        unsigned mask;
        if (simd) mask = wnode_test_simd(n, sr, best->t, !any, tnear);
        else mask = wnode_test_scalar(n, tr, best->t, !any, tnear);
        if (mask != 0) {
            // Start fetching every child the ray enters (prefetch_children).
            if (leaves == LEAVES_TRIANGLES) prefetch_children(b, n, mask);
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
        if (simd) hit_here = leaf_simd(b, ref, r, sr, stri, tc, best, inst_id, any, leaves);
        else hit_here = leaf_scalar(b, ref, r, tc, best, inst_id, any, leaves);
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

/// One ray through a wide BVH from its root, improving *best; true when anything was hit. With `leaves` not
/// LEAVES_ANY, the code for other kinds, with its out-of-line calls (around which every vector register would
/// have to be saved), is left out. An any-hit query with `occluder` not NULL tests the leaf *occluder first (a
/// leaf reference of b, or BVH_EMPTY) and leaves in it the leaf that answered, or BVH_EMPTY when none did.
static inline __attribute__((always_inline)) bool wide_run(const bvh *b, const ray *r, hit *best, uint32_t inst_id,
                                                           bool any, bool simd, int leaves, uint32_t *occluder) {
    uint32_t last = BVH_EMPTY; // the leaf to test first; *occluder is BVH_EMPTY unless a leaf answers
    if (any && occluder) {
        last = *occluder;
        *occluder = BVH_EMPTY;
    }
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
    stri.tr = NULL; // a mixed tree's triangle constants: made below or at its first triangle packet
    // A triangle-only BVH tests triangles in nearly every leaf: their constants are made once, up front; so does a
    // mixed one with few spheres (bvh.triangles_first).
    if (simd && (leaves == LEAVES_TRIANGLES || (leaves == LEAVES_ANY && b->triangles_first))) {
        tri_for(&tc, r);
        simd_tri_setup(&tc.tr, r->tmin, r->tmax, &stri);
    }
    bool found = false;
    // The leaf that blocked the caller's last shadow ray often blocks this one too (a path scattering inside a
    // glass ball: the ball), and one leaf test then answers without the walk down the tree. The answer is the
    // walk's: the boxes are conservative, so the walk reaches every leaf holding a hit.
    if (last != BVH_EMPTY) {
        bool h = simd ? leaf_simd(b, last, r, &sr, &stri, &tc, best, inst_id, any, leaves)
                      : leaf_scalar(b, last, r, &tc, best, inst_id, any, leaves);
        if (h) {
            *occluder = last;
            return true;
        }
    }
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
        if (st == STEP_FOUND) {
            if (occluder) *occluder = w.ref;
            return true;
        }
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
        if (any && h && occluder) *occluder = b->front;
    }
    return found;
}

#endif
