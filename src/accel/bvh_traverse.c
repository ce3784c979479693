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

/// Stack entry: a node or leaf reference and the distance at which the ray enters its box.
typedef struct stack_entry {
    uint32_t ref;
    float t;
} stack_entry;

enum { WIDE_STACK = BVH_MAX_DEPTH * (BVH_WIDTH - 1) + 1, BIN_STACK = BVH_MAX_DEPTH + 1 };

/// A leaf candidate is better than the best so far: nearer, or as near and of lower index (as brute force).
static inline bool better(float t, uint32_t prim, float tbest, uint32_t best) {
    return t < tbest || (t == tbest && prim < best);
}

// A ray with a NaN coordinate hits nothing (as in sphere_intersect); rejecting it up front also keeps
// NaN out of the box tests, where min/max would turn it into "every box is hit".
static inline bool ray_is_nan(const ray *r) {
    return isnan(r->o.x) || isnan(r->o.y) || isnan(r->o.z) || isnan(r->d.x) || isnan(r->d.y) || isnan(r->d.z);
}

/* ------------------------------------------------------------------------------------------------ */
/* Scalar box tests                                                                                   */

/// A ray prepared for box tests: t on axis k is box * inv[k] + noi[k] (one FMA); near/far pick the box
/// row (box[k] lower, box[3 + k] upper) the ray enters and leaves by.
typedef struct trav_ray {
    const ray *r;
    float inv[3], noi[3];
    int near[3], far[3];
} trav_ray;

static inline float clamp_dir(float d) { return fabsf(d) < DIR_EPSILON ? copysignf(DIR_EPSILON, d) : d; }

static inline trav_ray trav_setup(const ray *r) {
    trav_ray tr;
    tr.r = r;
    const float o[3] = {r->o.x, r->o.y, r->o.z}, d[3] = {r->d.x, r->d.y, r->d.z};
    for (int k = 0; k < 3; k++) {
        float inv = 1.0f / clamp_dir(d[k]);
        tr.inv[k] = inv;
        tr.noi[k] = -(o[k] * inv);
        tr.near[k] = inv < 0.0f ? 3 + k : k;
        tr.far[k] = inv < 0.0f ? k : 3 + k;
    }
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
    if (!b->nodes2 || ray_is_nan(r)) return false;
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
    bvh_sphere_hit(h, tbest, best);
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
        // Same operations in the same order as the SIMD path.
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

/// The ray broadcast into registers, with the box rows it enters (near) and leaves (far) by.
typedef struct simd_ray {
    __m256 inv[3], noi[3], tmin;
    pk ox, oy, oz, dx, dy, dz, a, ptmin, ptmax, tmin_nonneg;
    int near[3], far[3];
} simd_ray;

// Computes what trav_setup computes (the same IEEE operations, so the same values) with a handful of
// vector instructions; false for a ray with a NaN coordinate.
static inline bool simd_setup(const ray *r, simd_ray *s) {
    __m128 o = _mm_setr_ps(r->o.x, r->o.y, r->o.z, 0.0f), d = _mm_setr_ps(r->d.x, r->d.y, r->d.z, 1.0f);
    bool nan = _mm_movemask_ps(_mm_cmpunord_ps(o, d)) != 0;
    const __m128 sign = _mm_set1_ps(-0.0f), eps = _mm_set1_ps(DIR_EPSILON);
    __m128 tiny = _mm_cmplt_ps(_mm_andnot_ps(sign, d), eps);
    __m128 dc = _mm_blendv_ps(d, _mm_or_ps(_mm_and_ps(sign, d), eps), tiny);
    __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), dc);
    __m128 noi = _mm_xor_ps(_mm_mul_ps(o, inv), sign);
    int neg = _mm_movemask_ps(inv);
    s->inv[0] = _mm256_broadcastss_ps(inv);
    s->inv[1] = _mm256_broadcastss_ps(_mm_movehdup_ps(inv));
    s->inv[2] = _mm256_broadcastss_ps(_mm_movehl_ps(inv, inv));
    s->noi[0] = _mm256_broadcastss_ps(noi);
    s->noi[1] = _mm256_broadcastss_ps(_mm_movehdup_ps(noi));
    s->noi[2] = _mm256_broadcastss_ps(_mm_movehl_ps(noi, noi));
    for (int k = 0; k < 3; k++) {
        int n = (neg >> k) & 1;
        s->near[k] = k + 3 * n;
        s->far[k] = k + 3 - 3 * n;
    }
    s->tmin = _mm256_set1_ps(r->tmin);
    s->ox = PK(set1_ps)(r->o.x);
    s->oy = PK(set1_ps)(r->o.y);
    s->oz = PK(set1_ps)(r->o.z);
    s->dx = PK(set1_ps)(r->d.x);
    s->dy = PK(set1_ps)(r->d.y);
    s->dz = PK(set1_ps)(r->d.z);
    s->a = PK(set1_ps)(v3_dot(r->d, r->d));
    s->ptmin = PK(set1_ps)(r->tmin);
    s->ptmax = PK(set1_ps)(r->tmax);
    s->tmin_nonneg = PK(cmp_ps)(s->ptmin, PK(setzero_ps)(), _CMP_GE_OQ);
    return !nan;
}

static inline unsigned wnode_test_simd(const bvh_wnode *n, const simd_ray *s, float tlimit, float *tnear) {
    __m256 nx = _mm256_fmadd_ps(_mm256_load_ps(n->box[s->near[0]]), s->inv[0], s->noi[0]);
    __m256 ny = _mm256_fmadd_ps(_mm256_load_ps(n->box[s->near[1]]), s->inv[1], s->noi[1]);
    __m256 nz = _mm256_fmadd_ps(_mm256_load_ps(n->box[s->near[2]]), s->inv[2], s->noi[2]);
    __m256 fx = _mm256_fmadd_ps(_mm256_load_ps(n->box[s->far[0]]), s->inv[0], s->noi[0]);
    __m256 fy = _mm256_fmadd_ps(_mm256_load_ps(n->box[s->far[1]]), s->inv[1], s->noi[1]);
    __m256 fz = _mm256_fmadd_ps(_mm256_load_ps(n->box[s->far[2]]), s->inv[2], s->noi[2]);
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
    pk f2 = PK(add_ps)(PK(add_ps)(PK(mul_ps)(fx, fx), PK(mul_ps)(fy, fy)), PK(mul_ps)(fz, fz));
    pk c = PK(sub_ps)(f2, rr);
    // From outside (c > 0) and moving away (b < 0) both roots are negative: q < 0, t1 = q / a <= 0 and
    // t0 = c / q < 0, exact sign facts of the computed values, so no root can lie above tmin >= 0.
    pk away = PK(and_ps)(PK(and_ps)(PK(cmp_ps)(c, zero, _CMP_GT_OQ), PK(cmp_ps)(b, zero, _CMP_LT_OQ)), s->tmin_nonneg);
    pk ok = PK(andnot_ps)(away, PK(cmp_ps)(disc, zero, _CMP_GE_OQ));
    if (PK(movemask_ps)(ok) == 0) return 0; // the common case: the ray misses every sphere
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
#else
typedef struct simd_ray simd_ray; // never defined: the SIMD path is not compiled in
#endif

/* ------------------------------------------------------------------------------------------------ */
/* Wide traversal, shared by both paths (`simd` is a compile-time constant after inlining)           */

/// Where one ray's traversal stands: the next node or leaf, the stack depth and the best hit so far.
typedef struct trav_state {
    uint32_t ref, best;
    int sp;
    float tbest;
} trav_state;

enum { STEP_MORE, STEP_DONE, STEP_FOUND };

// One step of a traversal: visits st->ref (a node: choose the children to visit; a leaf: test it), then
// picks the next reference. STEP_DONE when nothing is left, STEP_FOUND when an any-hit query found one.
// The scalar path reads tr, the SIMD path sr.
static inline __attribute__((always_inline)) int wide_step(const bvh *b, const ray *r, const trav_ray *tr,
                                                          const simd_ray *sr, stack_entry *stack, trav_state *st,
                                                          bool any, bool simd) {
#if !BVH_SIMD
    (void)sr;
    (void)simd;
#endif
    uint32_t ref = st->ref;
    if (!(ref & BVH_LEAF)) {
        const bvh_wnode *n = &b->wnodes[ref];
        float tnear[BVH_WIDTH];
        unsigned mask;
#if BVH_SIMD
        if (simd) mask = wnode_test_simd(n, sr, st->tbest, tnear);
        else
#endif
            mask = wnode_test_scalar(n, tr, st->tbest, tnear);
        if (mask != 0) {
            unsigned rest = mask & (mask - 1);
            if (rest == 0) {
                st->ref = n->child[__builtin_ctz(mask)];
                return STEP_MORE;
            }
            if (!any && (rest & (rest - 1)) == 0) {
                // Two children (the common case): descend into the nearer, push the farther.
                int i0 = __builtin_ctz(mask), i1 = __builtin_ctz(rest);
                bool swap = tnear[i1] < tnear[i0];
                uint32_t c0 = n->child[i0], c1 = n->child[i1];
                stack[st->sp].ref = swap ? c0 : c1;
                stack[st->sp].t = swap ? tnear[i0] : tnear[i1];
                st->sp++;
                st->ref = swap ? c1 : c0;
                return STEP_MORE;
            }
            // Push every child entered, sorted so that the nearest is on top, and descend into it.
            int base = st->sp, sp = st->sp;
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
            st->ref = stack[--sp].ref;
            st->sp = sp;
            return STEP_MORE;
        }
    } else {
        bool found;
#if BVH_SIMD
        if (simd) found = leaf_simd(b, ref, sr, any, &st->tbest, &st->best);
        else
#endif
            found = leaf_scalar(b, ref, r, any, &st->tbest, &st->best);
        if (found) return STEP_FOUND;
    }
    // Pop the nearest pending subtree that can still hold a nearer hit.
    while (st->sp > 0) {
        stack_entry e = stack[--st->sp];
        if (e.t <= st->tbest) {
            st->ref = e.ref;
            return STEP_MORE;
        }
    }
    return STEP_DONE;
}

static inline trav_state trav_start(const bvh *b, const ray *r) {
    trav_state st = {b->root, UINT32_MAX, 0, r->tmax};
    return st;
}

static inline bool trav_result(const trav_state *st, hit *h) {
    if (st->best == UINT32_MAX) return false;
    bvh_sphere_hit(h, st->tbest, st->best);
    return true;
}

// One ray from the root to the end.
static inline __attribute__((always_inline)) bool wide_traverse(const bvh *b, const ray *r, hit *h, bool any,
                                                                bool simd) {
    if (b->root == BVH_EMPTY) return false;
    trav_ray tr;
#if BVH_SIMD
    simd_ray sr;
    if (simd) {
        if (!simd_setup(r, &sr)) return false;
    } else
#endif
    {
        if (ray_is_nan(r)) return false;
        tr = trav_setup(r);
    }
    stack_entry stack[WIDE_STACK];
    trav_state st = trav_start(b, r);
    int s;
#if BVH_SIMD
    while ((s = wide_step(b, r, &tr, &sr, stack, &st, any, simd)) == STEP_MORE) {
    }
#else
    while ((s = wide_step(b, r, &tr, NULL, stack, &st, any, simd)) == STEP_MORE) {
    }
#endif
    if (s == STEP_FOUND) return true;
    return trav_result(&st, h);
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

void bvh_intersect2(const bvh *b, const ray *r0, const ray *r1, hit *h0, hit *h1, bool *f0, bool *f1) {
#if BVH_SIMD
    *f0 = *f1 = false;
    if (b->root == BVH_EMPTY) return;
    simd_ray sr0, sr1;
    bool ok0 = simd_setup(r0, &sr0), ok1 = simd_setup(r1, &sr1);
    if (!ok0 || !ok1) {
        // A NaN ray ends at once; the other goes alone.
        if (ok0) *f0 = bvh_intersect(b, r0, h0);
        if (ok1) *f1 = bvh_intersect(b, r1, h1);
        return;
    }
    stack_entry stack0[WIDE_STACK], stack1[WIDE_STACK];
    trav_state st0 = trav_start(b, r0), st1 = trav_start(b, r1);
    // Alternate single steps of the two rays: two independent dependency chains in flight at once.
    int s0 = STEP_MORE, s1 = STEP_MORE;
    while (s0 == STEP_MORE && s1 == STEP_MORE) {
        s0 = wide_step(b, r0, NULL, &sr0, stack0, &st0, false, true);
        s1 = wide_step(b, r1, NULL, &sr1, stack1, &st1, false, true);
    }
    while (s0 == STEP_MORE) s0 = wide_step(b, r0, NULL, &sr0, stack0, &st0, false, true);
    while (s1 == STEP_MORE) s1 = wide_step(b, r1, NULL, &sr1, stack1, &st1, false, true);
    *f0 = trav_result(&st0, h0);
    *f1 = trav_result(&st1, h1);
#else
    *f0 = bvh_intersect(b, r0, h0);
    *f1 = bvh_intersect(b, r1, h1);
#endif
}
