// bvh_traverse.c — closest-hit and any-hit traversal of the binary and the wide BVH: nearest child
// first with a small stack, box tests of all children at once and sphere packets in one SIMD pass.
#include "accel/bvh.h"

#include <math.h>

#if BVH_SIMD
#include <immintrin.h>
#endif

// Relative widening of every box's exit distance, so that float rounding of the slab test (about 2^-23
// of t) never culls a box the ray touches; absolute errors are covered by the boxes' padding (sphere_box).
static const float SLAB_FAR_SCALE = 1.0f + 0x1p-20f;
// Direction components smaller than this are replaced by it (with their sign): finite inverses.
static const float DIR_EPSILON = 1e-20f;

/// A ray prepared for box tests: t on axis a is box * inv[a] + noi[a] (one FMA), near/far pick the
/// box row the ray enters and leaves by.
typedef struct trav_ray {
    const ray *r;
    float inv[3], noi[3];
    int near[3], far[3];
    float a; ///< d.d exactly as sphere_intersect computes it
} trav_ray;

static inline trav_ray trav_setup(const ray *r) {
    trav_ray tr;
    tr.r = r;
    const float o[3] = {r->o.x, r->o.y, r->o.z}, d[3] = {r->d.x, r->d.y, r->d.z};
    for (int k = 0; k < 3; k++) {
        float dk = fabsf(d[k]) < DIR_EPSILON ? copysignf(DIR_EPSILON, d[k]) : d[k];
        float inv = 1.0f / dk;
        tr.inv[k] = inv;
        tr.noi[k] = -(o[k] * inv);
        tr.near[k] = inv >= 0.0f ? k : 3 + k;
        tr.far[k] = inv >= 0.0f ? 3 + k : k;
    }
    tr.a = v3_dot(r->d, r->d);
    return tr;
}

// t of a box plane: one fused multiply-add (b - o) / d = b * (1/d) - o * (1/d).
static inline float slab_t(float b, float inv, float noi) {
#if defined(__FMA__) || defined(FP_FAST_FMAF)
    return fmaf(b, inv, noi);
#else
    return b * inv + noi; // without FMA hardware fmaf is a slow library call; the box test is conservative anyway
#endif
}

// max/min with the operand order of SSE maxps/minps, so the scalar and SIMD paths agree bit for bit.
static inline float max_sse(float a, float b) { return a > b ? a : b; }
static inline float min_sse(float a, float b) { return a < b ? a : b; }

/// A leaf candidate is better than the best so far: nearer, or as near and of lower index (as brute force).
static inline bool better(float t, uint32_t prim, float tbest, uint32_t best) {
    return t < tbest || (t == tbest && prim < best);
}

/// Stack entry: a node or leaf reference and the distance at which the ray enters its box.
typedef struct stack_entry {
    uint32_t ref;
    float t;
} stack_entry;

enum { WIDE_STACK = BVH_MAX_DEPTH * (BVH_WIDTH - 1) + 1, BIN_STACK = BVH_MAX_DEPTH + 1 };

/* ------------------------------------------------------------------------------------------------ */
/* Binary BVH (scalar)                                                                                */

// Entry distance of the ray into a binary node's box, or +inf when it misses within (tmin, tlimit].
static inline float box2_enter(const bvh2_node *n, const trav_ray *tr, float tlimit) {
    float tn = tr->r->tmin, tf = INFINITY;
    for (int k = 0; k < 3; k++) {
        tn = max_sse(slab_t(n->box[tr->near[k]], tr->inv[k], tr->noi[k]), tn);
        tf = min_sse(slab_t(n->box[tr->far[k]], tr->inv[k], tr->noi[k]), tf);
    }
    tf = min_sse(tf * SLAB_FAR_SCALE, tlimit);
    return tn <= tf ? tn : INFINITY;
}

// Nearest root of one primitive in the ray's own interval (tmin, tmax), by its kind.
static inline bool prim_hit(const bvh *b, prim_ref ref, const ray *r, float *t) {
    switch ((prim_kind)ref.kind) {
    case PRIM_SPHERE: {
        const sphere *s = &b->spheres[ref.index];
        return sphere_intersect(s->center, s->radius, r, r->tmin, r->tmax, t);
    }
    }
    return false;
}

static bool bin_traverse(const bvh *b, const ray *r, hit *h, bool any) {
    if (!b->nodes2) return false;
    trav_ray tr = trav_setup(r);
    float tbest = r->tmax;
    uint32_t best = UINT32_MAX;
    stack_entry stack[BIN_STACK];
    int sp = 0;
    if (box2_enter(&b->nodes2[0], &tr, tbest) == INFINITY) return false;
    uint32_t id = 0;
    for (;;) {
        const bvh2_node *n = &b->nodes2[id];
        if (n->count == 0) {
            uint32_t c0 = id + 1, c1 = n->offset;
            float t0 = box2_enter(&b->nodes2[c0], &tr, tbest), t1 = box2_enter(&b->nodes2[c1], &tr, tbest);
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
                float t;
                if (!prim_hit(b, ref, r, &t)) continue;
                if (any) return true;
                if (better(t, ref.index, tbest, best)) {
                    tbest = t;
                    best = ref.index;
                }
            }
        }
        // Pop the nearest pending subtree that can still hold a nearer hit.
        for (;;) {
            if (sp == 0) goto done;
            stack_entry e = stack[--sp];
            if (e.t <= tbest) { id = e.ref; break; }
        }
    }
done:
    if (best == UINT32_MAX) return false;
    h->t = tbest;
    h->prim = best;
    return true;
}

bool bvh2_intersect(const bvh *b, const ray *r, hit *h) { return bin_traverse(b, r, h, false); }

bool bvh2_occluded(const bvh *b, const ray *r) {
    hit h;
    return bin_traverse(b, r, &h, true);
}

/* ------------------------------------------------------------------------------------------------ */
/* Wide BVH, scalar path                                                                              */

// Box tests of every child of a wide node; returns the mask of children the ray enters before
// tlimit, and their entry distances in tnear.
static inline unsigned wnode_test_scalar(const bvh_wnode *n, const trav_ray *tr, float tlimit, float *tnear) {
    unsigned mask = 0;
    for (int i = 0; i < BVH_WIDTH; i++) {
        // Same operation order as the SIMD path: per axis, then combined with the ray interval.
        float nx = slab_t(n->box[tr->near[0]][i], tr->inv[0], tr->noi[0]);
        float ny = slab_t(n->box[tr->near[1]][i], tr->inv[1], tr->noi[1]);
        float nz = slab_t(n->box[tr->near[2]][i], tr->inv[2], tr->noi[2]);
        float fx = slab_t(n->box[tr->far[0]][i], tr->inv[0], tr->noi[0]);
        float fy = slab_t(n->box[tr->far[1]][i], tr->inv[1], tr->noi[1]);
        float fz = slab_t(n->box[tr->far[2]][i], tr->inv[2], tr->noi[2]);
        float tn = max_sse(max_sse(nx, ny), max_sse(nz, tr->r->tmin));
        float tf = min_sse(min_sse(fx, fy), fz) * SLAB_FAR_SCALE;
        tf = min_sse(tf, tlimit);
        tnear[i] = tn;
        if (tn <= tf) mask |= 1u << i;
    }
    return mask;
}

// Tests one leaf's packets; closest hit updates (*tbest, *best), any-hit returns true at once.
static inline bool leaf_scalar(const bvh *b, uint32_t ref, const ray *r, bool any, float *tbest, uint32_t *best) {
    const bvh_slot *slot = &b->slots[ref & ~BVH_LEAF];
    for (;;) {
        const bvh_packet_header *hd = (const bvh_packet_header *)(const void *)slot;
        switch ((prim_kind)hd->kind) {
        case PRIM_SPHERE: {
            const bvh_sphere_packet *p = (const bvh_sphere_packet *)(const void *)slot;
            for (uint32_t k = 0; k < hd->count; k++) {
                float t;
                if (!sphere_intersect(v3(p->cx[k], p->cy[k], p->cz[k]), p->radius[k], r, r->tmin, r->tmax, &t))
                    continue;
                if (any) return true;
                if (better(t, p->prim[k], *tbest, *best)) {
                    *tbest = t;
                    *best = p->prim[k];
                }
            }
            break;
        }
        }
        if (hd->last) return false;
        slot += hd->slots;
    }
}

/* ------------------------------------------------------------------------------------------------ */
/* Wide BVH, SIMD path (AVX2 + FMA)                                                                  */

#if BVH_SIMD
// Lanes of a leaf packet: AVX for 8 primitives, SSE for 4.
#if BVH_PACKET == 8
typedef __m256 pk;
#define PK(op) _mm256_##op
#elif BVH_PACKET == 4
typedef __m128 pk;
#define PK(op) _mm_##op
#else
#error "BVH_PACKET must be 4 or 8"
#endif

/// The ray broadcast into registers.
typedef struct simd_ray {
    __m256 inv[3], noi[3], tmin;
    pk ox, oy, oz, dx, dy, dz, a, ptmin, ptmax;
} simd_ray;

static inline simd_ray simd_setup(const trav_ray *tr) {
    simd_ray s;
    for (int k = 0; k < 3; k++) {
        s.inv[k] = _mm256_set1_ps(tr->inv[k]);
        s.noi[k] = _mm256_set1_ps(tr->noi[k]);
    }
    s.tmin = _mm256_set1_ps(tr->r->tmin);
    s.ox = PK(set1_ps)(tr->r->o.x);
    s.oy = PK(set1_ps)(tr->r->o.y);
    s.oz = PK(set1_ps)(tr->r->o.z);
    s.dx = PK(set1_ps)(tr->r->d.x);
    s.dy = PK(set1_ps)(tr->r->d.y);
    s.dz = PK(set1_ps)(tr->r->d.z);
    s.a = PK(set1_ps)(tr->a);
    s.ptmin = PK(set1_ps)(tr->r->tmin);
    s.ptmax = PK(set1_ps)(tr->r->tmax);
    return s;
}

static inline unsigned wnode_test_simd(const bvh_wnode *n, const trav_ray *tr, const simd_ray *s, float tlimit,
                                       float *tnear) {
    __m256 nx = _mm256_fmadd_ps(_mm256_load_ps(n->box[tr->near[0]]), s->inv[0], s->noi[0]);
    __m256 ny = _mm256_fmadd_ps(_mm256_load_ps(n->box[tr->near[1]]), s->inv[1], s->noi[1]);
    __m256 nz = _mm256_fmadd_ps(_mm256_load_ps(n->box[tr->near[2]]), s->inv[2], s->noi[2]);
    __m256 fx = _mm256_fmadd_ps(_mm256_load_ps(n->box[tr->far[0]]), s->inv[0], s->noi[0]);
    __m256 fy = _mm256_fmadd_ps(_mm256_load_ps(n->box[tr->far[1]]), s->inv[1], s->noi[1]);
    __m256 fz = _mm256_fmadd_ps(_mm256_load_ps(n->box[tr->far[2]]), s->inv[2], s->noi[2]);
    __m256 tn = _mm256_max_ps(_mm256_max_ps(nx, ny), _mm256_max_ps(nz, s->tmin));
    __m256 tf = _mm256_mul_ps(_mm256_min_ps(_mm256_min_ps(fx, fy), fz), _mm256_set1_ps(SLAB_FAR_SCALE));
    tf = _mm256_min_ps(tf, _mm256_set1_ps(tlimit));
    _mm256_storeu_ps(tnear, tn);
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ));
}

// A packet of spheres at once, each lane computing exactly what sphere_intersect computes (same
// operations, same order, same fused multiply-adds), so t is bit-identical to the scalar test.
// Returns the mask of lanes with a root in (tmin, tmax) and those roots in t_out.
static inline unsigned spheres_simd(const bvh_sphere_packet *p, const simd_ray *s, pk *t_out) {
    pk fx = PK(sub_ps)(s->ox, PK(load_ps)(p->cx));
    pk fy = PK(sub_ps)(s->oy, PK(load_ps)(p->cy));
    pk fz = PK(sub_ps)(s->oz, PK(load_ps)(p->cz));
    pk rad = PK(load_ps)(p->radius);
    const pk sign = PK(set1_ps)(-0.0f), zero = PK(setzero_ps)();
    // b = -(f.d)
    pk fd = PK(add_ps)(PK(add_ps)(PK(mul_ps)(fx, s->dx), PK(mul_ps)(fy, s->dy)), PK(mul_ps)(fz, s->dz));
    pk b = PK(xor_ps)(fd, sign);
    pk ba = PK(div_ps)(b, s->a);
    pk lx = PK(fmadd_ps)(s->dx, ba, fx), ly = PK(fmadd_ps)(s->dy, ba, fy), lz = PK(fmadd_ps)(s->dz, ba, fz);
    pk rr = PK(mul_ps)(rad, rad);
    pk l2 = PK(add_ps)(PK(add_ps)(PK(mul_ps)(lx, lx), PK(mul_ps)(ly, ly)), PK(mul_ps)(lz, lz));
    pk disc = PK(sub_ps)(rr, l2);
    pk ok = PK(cmp_ps)(disc, zero, _CMP_GE_OQ);
    if (PK(movemask_ps)(ok) == 0) return 0;

    pk f2 = PK(add_ps)(PK(add_ps)(PK(mul_ps)(fx, fx), PK(mul_ps)(fy, fy)), PK(mul_ps)(fz, fz));
    pk c = PK(sub_ps)(f2, rr);
    pk root = PK(sqrt_ps)(PK(mul_ps)(s->a, disc));
    pk q = PK(add_ps)(b, PK(or_ps)(PK(andnot_ps)(sign, root), PK(and_ps)(sign, b))); // b + copysign(root, b)
    pk t0 = PK(div_ps)(c, q), t1 = PK(div_ps)(q, s->a);
    t0 = PK(blendv_ps)(t0, t1, PK(cmp_ps)(q, zero, _CMP_EQ_OQ));
    pk swap = PK(cmp_ps)(t0, t1, _CMP_GT_OQ);
    pk lo = PK(blendv_ps)(t0, t1, swap), hi = PK(blendv_ps)(t1, t0, swap);
    pk in0 = PK(and_ps)(PK(cmp_ps)(lo, s->ptmin, _CMP_GT_OQ), PK(cmp_ps)(lo, s->ptmax, _CMP_LT_OQ));
    pk in1 = PK(and_ps)(PK(cmp_ps)(hi, s->ptmin, _CMP_GT_OQ), PK(cmp_ps)(hi, s->ptmax, _CMP_LT_OQ));
    *t_out = PK(blendv_ps)(hi, lo, in0);
    return (unsigned)PK(movemask_ps)(PK(and_ps)(ok, PK(or_ps)(in0, in1)));
}

static inline bool leaf_simd(const bvh *b, uint32_t ref, const simd_ray *s, bool any, float *tbest, uint32_t *best) {
    const bvh_slot *slot = &b->slots[ref & ~BVH_LEAF];
    for (;;) {
        const bvh_packet_header *hd = (const bvh_packet_header *)(const void *)slot;
        switch ((prim_kind)hd->kind) {
        case PRIM_SPHERE: {
            const bvh_sphere_packet *p = (const bvh_sphere_packet *)(const void *)slot;
            pk tv;
            unsigned mask = spheres_simd(p, s, &tv);
            if (mask) {
                if (any) return true;
                _Alignas(32) float t[BVH_PACKET];
                PK(store_ps)(t, tv);
                do {
                    int k = __builtin_ctz(mask);
                    mask &= mask - 1;
                    if (better(t[k], p->prim[k], *tbest, *best)) {
                        *tbest = t[k];
                        *best = p->prim[k];
                    }
                } while (mask);
            }
            break;
        }
        }
        if (hd->last) return false;
        slot += hd->slots;
    }
}
#endif

/* ------------------------------------------------------------------------------------------------ */
/* Wide traversal, shared by both paths (`simd` is a compile-time constant after inlining)           */

static inline __attribute__((always_inline)) bool wide_traverse(const bvh *b, const ray *r, hit *h, bool any,
                                                                bool simd) {
    if (b->root == BVH_EMPTY) return false;
    trav_ray tr = trav_setup(r);
#if BVH_SIMD
    simd_ray sr = simd_setup(&tr);
#else
    (void)simd;
#endif
    float tbest = r->tmax;
    uint32_t best = UINT32_MAX;
    stack_entry stack[WIDE_STACK];
    int sp = 0;
    uint32_t ref = b->root;
    for (;;) {
        if (!(ref & BVH_LEAF)) {
            const bvh_wnode *n = &b->wnodes[ref];
            float tnear[BVH_WIDTH];
            unsigned mask;
            // The box tests do not use tbest: a data dependence on the last leaf test would put its whole
            // latency in front of every node that follows. The nearest-hit culling is a branch instead,
            // which the processor predicts and runs past.
#if BVH_SIMD
            if (simd) mask = wnode_test_simd(n, &tr, &sr, r->tmax, tnear);
            else
#endif
                mask = wnode_test_scalar(n, &tr, r->tmax, tnear);
            if (mask != 0) {
                unsigned rest = mask & (mask - 1);
                if (rest == 0) {
                    int i = __builtin_ctz(mask);
                    if (tnear[i] <= tbest) {
                        ref = n->child[i];
                        continue;
                    }
                } else if (!any && (rest & (rest - 1)) == 0) {
                    // Two children (the common case): push the farther, descend into the nearer.
                    int i0 = __builtin_ctz(mask), i1 = __builtin_ctz(rest);
                    bool swap = tnear[i1] < tnear[i0];
                    uint32_t c0 = n->child[i0], c1 = n->child[i1];
                    float t0 = tnear[i0], t1 = tnear[i1];
                    stack[sp].ref = swap ? c0 : c1;
                    stack[sp].t = swap ? t0 : t1;
                    sp++;
                    if ((swap ? t1 : t0) <= tbest) {
                        ref = swap ? c1 : c0;
                        continue;
                    }
                } else {
                    // Push every child entered, sorted so that the nearest is on top, then pop it.
                    int base = sp;
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
                }
            }
        } else {
            bool found;
#if BVH_SIMD
            if (simd) found = leaf_simd(b, ref, &sr, any, &tbest, &best);
            else
#endif
                found = leaf_scalar(b, ref, r, any, &tbest, &best);
            if (found) return true;
        }
        // Pop the nearest pending subtree that can still hold a nearer hit.
        for (;;) {
            if (sp == 0) goto done;
            stack_entry e = stack[--sp];
            if (e.t <= tbest) {
                ref = e.ref;
                break;
            }
        }
    }
done:
    if (best == UINT32_MAX) return false;
    h->t = tbest;
    h->prim = best;
    return true;
}

bool bvh_intersect_scalar(const bvh *b, const ray *r, hit *h) { return wide_traverse(b, r, h, false, false); }

bool bvh_occluded_scalar(const bvh *b, const ray *r) {
    hit h;
    return wide_traverse(b, r, &h, true, false);
}

bool bvh_intersect(const bvh *b, const ray *r, hit *h) { return wide_traverse(b, r, h, false, BVH_SIMD); }

bool bvh_occluded(const bvh *b, const ray *r) {
    hit h;
    return wide_traverse(b, r, &h, true, BVH_SIMD);
}
