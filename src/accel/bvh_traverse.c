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
/* Primitives tested one at a time                                                                    */

/// Per-ray constants of the watertight triangle test, made the first time a quad or triangle needs them.
typedef struct tri_cache {
    bool ready;
    tri_ray tr;
} tri_cache;

static inline const tri_ray *tri_for(tri_cache *c, const ray *r) {
    if (!c->ready) {
        c->tr = tri_ray_make(r);
        c->ready = true;
    }
    return &c->tr;
}

// Keeps candidate c if it beats *best (bvh_better); true when it did.
static inline bool offer(hit *best, hit c) {
    if (!bvh_better(&c, best)) return false;
    *best = c;
    return true;
}

/// How instances are entered: the structure of the BLAS and which traversal path runs it.
typedef enum trav_mode { MODE_WIDE_SIMD, MODE_WIDE_SCALAR, MODE_BINARY } trav_mode;

static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode);

// An instance: the ray taken to object space (direction not normalised, so t keeps its meaning), then the
// mesh's BVH or the object-space sphere. True when it hit (any-hit queries stop there).
static bool instance_hit(const bvh *b, uint32_t index, const ray *r, hit *best, bool any, trav_mode mode) {
    const instance *in = &b->instances[index];
    ray o = mat4_apply_ray(&in->xf.inv, r);
    if (in->kind == INSTANCE_SPHERE) {
        const sphere *sp = &b->instance_spheres[in->index];
        float t;
        if (!sphere_intersect(sp->center, sp->radius, &o, o.tmin, o.tmax, &t)) return false;
        offer(best, (hit){t, in->index, HIT_SPHERE, index, 0.0f, 0.0f});
        return true;
    }
    return blas_traverse(&b->blas[in->index], &o, best, index, any, mode);
}

// One primitive that is not tested in SIMD: a quad, a triangle of b's mesh, an instance (or a sphere in
// the binary BVH). `inst_id` is the instance whose mesh b is, or HIT_NO_INSTANCE. True when it hit.
static inline bool prim_hit(const bvh *b, uint32_t kind, uint32_t index, const ray *r, tri_cache *tc, hit *best,
                            uint32_t inst_id, bool any, trav_mode mode) {
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
        tri_hit th;
        if (!mesh_intersect_triangle(b->mesh, index, tri_for(tc, r), r->tmin, r->tmax, &th)) return false;
        offer(best, (hit){th.t, index, HIT_TRIANGLE, inst_id, th.b1, th.b2});
        return true;
    }
    case PRIM_INSTANCE: return instance_hit(b, index, r, best, any, mode);
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
        if (!prim_hit(b, p->h.kind, p->prim[k], r, tc, &best, inst_id, any, mode)) continue;
        *hit_any = true;
        if (any) break;
    }
    return best;
}

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

static bool bin_run(const bvh *b, const ray *r, hit *best, uint32_t inst_id, bool any) {
    if (!b->nodes2 || ray_is_nan(r)) return false;
    trav_ray tr = trav_setup(r);
    tri_cache tc = {.ready = false};
    stack_entry stack[BIN_STACK];
    int sp = 0;
    bool found = false;
    if (box2_enter(&b->nodes2[0], &tr, best->t) == INFINITY) return false;
    uint32_t id = 0;
    for (;;) {
        const bvh2_node *n = &b->nodes2[id];
        if (n->count == 0) {
            uint32_t c0 = id + 1, c1 = n->offset;
            float t0 = box2_enter(&b->nodes2[c0], &tr, best->t), t1 = box2_enter(&b->nodes2[c1], &tr, best->t);
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
                if (!prim_hit(b, ref.kind, ref.index, r, &tc, best, inst_id, any, MODE_BINARY)) continue;
                found = true;
                if (any) return true;
            }
        }
        // Pop the nearest pending subtree that can still hold a nearer hit.
        for (;;) {
            if (sp == 0) return found;
            stack_entry e = stack[--sp];
            if (e.t <= best->t) { id = e.ref; break; }
        }
    }
}

bool bvh2_intersect(const bvh *b, const ray *r, hit *h) {
    hit best = bvh_no_hit(r);
    if (!bin_run(b, r, &best, HIT_NO_INSTANCE, false)) return false;
    *h = best;
    return true;
}

bool bvh2_occluded(const bvh *b, const ray *r) {
    hit best = bvh_no_hit(r);
    return bin_run(b, r, &best, HIT_NO_INSTANCE, true);
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
        // The slab distances as second operands: an empty slot's NaN reaches tn, and tn <= tf fails.
        float tn = max_sse(max_sse(tr->r->tmin, nx), max_sse(ny, nz));
        float tf = min_sse(min_sse(fx, fy), fz) * SLAB_FAR_SCALE;
        tf = min_sse(tf, tlimit);
        tnear[i] = tn;
        if (tn <= tf) mask |= 1u << i;
    }
    return mask;
}

// Tests one leaf's packets one primitive at a time. True when something was hit.
static inline bool leaf_scalar(const bvh *b, uint32_t ref, const ray *r, tri_cache *tc, hit *best, uint32_t inst_id,
                               bool any, bool generic) {
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
        } else if (generic) {
            bool h;
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
    __m256 inv[3], noi[3];
    pk ox, oy, oz, dx, dy, dz, a, inv_a, tmin, tmax, tmin_nonneg;
} simd_ray;

// Computes what trav_setup computes (the same IEEE operations, so the same values); false for a ray with a
// NaN coordinate. Every traversal pays for it once, so it broadcasts from memory rather than shuffling. The
// ray was just written field by field: loads that span several of those stores would wait for them to
// retire (no store-to-load forwarding), so every load here reads one float.
static inline bool simd_setup(const ray *r, simd_ray *s) {
    __m128 o = _mm_setr_ps(r->o.x, r->o.y, r->o.z, 0.0f), d = _mm_setr_ps(r->d.x, r->d.y, r->d.z, 1.0f);
    if (_mm_movemask_ps(_mm_cmpunord_ps(o, d)) != 0) return false;
    const __m128 sign = _mm_set1_ps(-0.0f), eps = _mm_set1_ps(DIR_EPSILON);
    __m128 tiny = _mm_cmplt_ps(_mm_andnot_ps(sign, d), eps);
    __m128 dc = _mm_blendv_ps(d, _mm_or_ps(_mm_and_ps(sign, d), eps), tiny);
    __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), dc);
    __m128 noi = _mm_xor_ps(_mm_mul_ps(o, inv), sign);
    s->inv[0] = _mm256_broadcastss_ps(inv);
    s->inv[1] = _mm256_broadcastss_ps(_mm_movehdup_ps(inv));
    s->inv[2] = _mm256_broadcastss_ps(_mm_movehl_ps(inv, inv));
    s->noi[0] = _mm256_broadcastss_ps(noi);
    s->noi[1] = _mm256_broadcastss_ps(_mm_movehdup_ps(noi));
    s->noi[2] = _mm256_broadcastss_ps(_mm_movehl_ps(noi, noi));
    s->ox = PK(broadcast_ss)(&r->o.x);
    s->oy = PK(broadcast_ss)(&r->o.y);
    s->oz = PK(broadcast_ss)(&r->o.z);
    s->dx = PK(broadcast_ss)(&r->d.x);
    s->dy = PK(broadcast_ss)(&r->d.y);
    s->dz = PK(broadcast_ss)(&r->d.z);
    s->tmin = PK(broadcast_ss)(&r->tmin);
    s->tmax = PK(broadcast_ss)(&r->tmax);
    float a = v3_dot(r->d, r->d);
    s->a = PK(set1_ps)(a);
    s->inv_a = PK(set1_ps)(1.0f / a);
    s->tmin_nonneg = PK(cmp_ps)(s->tmin, PK(setzero_ps)(), _CMP_GE_OQ);
    return true;
}

static inline unsigned wnode_test_simd(const bvh_wnode *n, const simd_ray *s, float tlimit, float *tnear) {
    // Both planes of every slab, the nearer by min and the farther by max: the same values as choosing the
    // rows by the direction's signs (trav_setup's near and far), without per-ray row offsets to keep live.
    __m256 lx = _mm256_fmadd_ps(_mm256_load_ps(n->box[0]), s->inv[0], s->noi[0]);
    __m256 ly = _mm256_fmadd_ps(_mm256_load_ps(n->box[1]), s->inv[1], s->noi[1]);
    __m256 lz = _mm256_fmadd_ps(_mm256_load_ps(n->box[2]), s->inv[2], s->noi[2]);
    __m256 hx = _mm256_fmadd_ps(_mm256_load_ps(n->box[3]), s->inv[0], s->noi[0]);
    __m256 hy = _mm256_fmadd_ps(_mm256_load_ps(n->box[4]), s->inv[1], s->noi[1]);
    __m256 hz = _mm256_fmadd_ps(_mm256_load_ps(n->box[5]), s->inv[2], s->noi[2]);
    __m256 nx = _mm256_min_ps(lx, hx), ny = _mm256_min_ps(ly, hy), nz = _mm256_min_ps(lz, hz);
    __m256 fx = _mm256_max_ps(lx, hx), fy = _mm256_max_ps(ly, hy), fz = _mm256_max_ps(lz, hz);
#if BVH_PACKET == 8
    __m256 tmin = s->tmin;
#else
    __m256 tmin = _mm256_set_m128(s->tmin, s->tmin);
#endif
    // Operand order as in wnode_test_scalar: an empty slot's NaN reaches tn.
    __m256 tn = _mm256_max_ps(_mm256_max_ps(tmin, nx), _mm256_max_ps(ny, nz));
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
    pk rr = PK(mul_ps)(rad, rad);
    pk f2 = PK(add_ps)(PK(add_ps)(PK(mul_ps)(fx, fx), PK(mul_ps)(fy, fy)), PK(mul_ps)(fz, fz));
    pk c = PK(sub_ps)(f2, rr);
    // From outside (c > 0) and moving away (b < 0) both roots are negative: q < 0, t1 = q (1/a) <= 0 and
    // t0 = c / q < 0, exact sign facts of the computed values, so no root can lie above tmin >= 0.
    pk away = PK(and_ps)(PK(and_ps)(PK(cmp_ps)(c, zero, _CMP_GT_OQ), PK(cmp_ps)(b, zero, _CMP_LT_OQ)), s->tmin_nonneg);
    // Early rejection without the division (the common case: the ray misses every sphere). a c - b^2 is a
    // times (squared distance from the centre to the line - r^2). Where it exceeds 2^-12 a (|f|^2 + r^2), far
    // beyond the rounding of it and of the full test below (about 2^-20 of that), the full test finds
    // disc < 0 too: leaving such lanes out changes no result. NaN lanes (unused) compare false.
    pk gap = PK(fmsub_ps)(s->a, c, PK(mul_ps)(b, b));
    pk bound = PK(mul_ps)(PK(mul_ps)(s->a, PK(set1_ps)(0x1p-12f)), PK(add_ps)(f2, rr));
    if (PK(movemask_ps)(PK(andnot_ps)(away, PK(cmp_ps)(gap, bound, _CMP_LE_OQ))) == 0) return 0;
    pk ba = PK(mul_ps)(b, s->inv_a);
    pk lx = PK(fmadd_ps)(s->dx, ba, fx), ly = PK(fmadd_ps)(s->dy, ba, fy), lz = PK(fmadd_ps)(s->dz, ba, fz);
    pk l2 = PK(add_ps)(PK(add_ps)(PK(mul_ps)(lx, lx), PK(mul_ps)(ly, ly)), PK(mul_ps)(lz, lz));
    pk disc = PK(sub_ps)(rr, l2);
    pk ok = PK(andnot_ps)(away, PK(cmp_ps)(disc, zero, _CMP_GE_OQ));
    if (PK(movemask_ps)(ok) == 0) return 0;
    pk root = PK(sqrt_ps)(PK(mul_ps)(s->a, disc));
    pk q = PK(add_ps)(b, PK(or_ps)(PK(andnot_ps)(sign, root), PK(and_ps)(sign, b))); // b + copysign(root, b)
    pk t0 = PK(div_ps)(c, q), t1 = PK(mul_ps)(q, s->inv_a);
    t0 = PK(blendv_ps)(t0, t1, PK(cmp_ps)(q, zero, _CMP_EQ_OQ));
    pk swap = PK(cmp_ps)(t0, t1, _CMP_GT_OQ);
    pk lo = PK(blendv_ps)(t0, t1, swap), hi = PK(blendv_ps)(t1, t0, swap);
    pk in0 = PK(and_ps)(PK(cmp_ps)(lo, s->tmin, _CMP_GT_OQ), PK(cmp_ps)(lo, s->tmax, _CMP_LT_OQ));
    pk in1 = PK(and_ps)(PK(cmp_ps)(hi, s->tmin, _CMP_GT_OQ), PK(cmp_ps)(hi, s->tmax, _CMP_LT_OQ));
    *t_out = PK(blendv_ps)(hi, lo, in0);
    return (unsigned)PK(movemask_ps)(PK(and_ps)(ok, PK(or_ps)(in0, in1)));
}

// Offers the hits of spheres_simd (lanes `mask` of packet p, at distances tv) to *best.
static inline void offer_spheres(hit *best, const bvh_sphere_packet *p, unsigned mask, pk tv, uint32_t inst_id) {
    _Alignas(32) float t[BVH_PACKET];
    PK(store_ps)(t, tv);
    do {
        int k = __builtin_ctz(mask);
        mask &= mask - 1;
        if (t[k] <= best->t) offer(best, (hit){t[k], p->prim[k], HIT_SPHERE, inst_id, 0.0f, 0.0f});
    } while (mask);
}

// Tests one leaf: spheres in SIMD packets, everything else one at a time. True when something was hit.
static inline __attribute__((always_inline)) bool leaf_simd(const bvh *b, uint32_t ref, const ray *r,
                                                            const simd_ray *s, tri_cache *tc, hit *best,
                                                            uint32_t inst_id, bool any, bool generic) {
    const bvh_slot *slot = &b->slots[ref & ~BVH_LEAF];
    bool found = false;
    for (;;) {
        const bvh_packet_header *hd = (const bvh_packet_header *)(const void *)slot;
        if (!generic || hd->kind == PRIM_SPHERE) { // a sphere-only BVH holds nothing else
            const bvh_sphere_packet *p = (const bvh_sphere_packet *)(const void *)slot;
            pk tv;
            unsigned mask = spheres_simd(p, s, &tv);
            if (mask) {
                found = true;
                if (any) return true;
                offer_spheres(best, p, mask, tv, inst_id);
            }
        } else if (generic) {
            bool h;
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
                                                          const simd_ray *sr, tri_cache *tc, stack_entry *stack,
                                                          walk *w, hit *best, uint32_t inst_id, bool *found,
                                                          bool any, bool simd, bool generic) {
#if !BVH_SIMD
    (void)sr;
    (void)simd;
#endif
    uint32_t ref = w->ref;
    if (!(ref & BVH_LEAF)) {
        const bvh_wnode *n = &b->wnodes[ref];
        float tnear[BVH_WIDTH];
        unsigned mask;
#if BVH_SIMD
        if (simd) mask = wnode_test_simd(n, sr, best->t, tnear);
        else
#endif
            mask = wnode_test_scalar(n, tr, best->t, tnear);
        if (mask != 0) {
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
        if (simd) hit_here = leaf_simd(b, ref, r, sr, tc, best, inst_id, any, generic);
        else
#endif
            hit_here = leaf_scalar(b, ref, r, tc, best, inst_id, any, generic);
        if (hit_here) {
            *found = true;
            if (any) return STEP_FOUND;
        }
    }
    // Pop the nearest pending subtree that can still hold a nearer hit.
    while (w->sp > 0) {
        stack_entry e = stack[--w->sp];
        if (e.t <= best->t) {
            w->ref = e.ref;
            return STEP_MORE;
        }
    }
    return STEP_DONE;
}

// One ray through a wide BVH from its root, improving *best; true when anything was hit. With `generic`
// false the BVH holds only spheres: the code for other kinds, with its out-of-line calls (around which
// every vector register would have to be saved), is left out.
static inline __attribute__((always_inline)) bool wide_run(const bvh *b, const ray *r, hit *best, uint32_t inst_id,
                                                           bool any, bool simd, bool generic) {
    if (b->root == BVH_EMPTY && b->front == BVH_EMPTY) return false;
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
    tri_cache tc = {.ready = false};
    bool found = false;
#if BVH_SIMD
    // In a sphere-only BVH the huge spheres are one sphere packet. Its test does not depend on the tree's, so
    // a closest-hit query makes it first, where the processor overlaps it with the first tree steps, and
    // merges its hits after the tree (+1.3 to +1.6% on rtiow-final; docs/benchmarks.md).
    bool front_first = simd && !any && !generic && b->front != BVH_EMPTY;
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
        while ((st = wide_step(b, r, &tr, &sr, &tc, stack, &w, best, inst_id, &found, any, simd, generic)) == STEP_MORE) {
        }
#else
        int st;
        while ((st = wide_step(b, r, &tr, NULL, &tc, stack, &w, best, inst_id, &found, any, simd, generic)) == STEP_MORE) {
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
        if (simd) h = leaf_simd(b, b->front, r, &sr, &tc, best, inst_id, any, generic);
        else
#endif
            h = leaf_scalar(b, b->front, r, &tc, best, inst_id, any, generic);
        found = found || h;
    }
    return found;
}

static bool blas_traverse(const bvh *blas, const ray *r, hit *best, uint32_t inst_id, bool any, trav_mode mode) {
    switch (mode) {
#if BVH_SIMD
    case MODE_WIDE_SIMD: return wide_run(blas, r, best, inst_id, any, true, true);
#else
    case MODE_WIDE_SIMD: return wide_run(blas, r, best, inst_id, any, false, true);
#endif
    case MODE_WIDE_SCALAR: return wide_run(blas, r, best, inst_id, any, false, true);
    case MODE_BINARY: return bin_run(blas, r, best, inst_id, any);
    }
    return false;
}

// The closest-hit and any-hit entry points, one function per combination so that each is compiled
// for exactly its case (the sphere-only ones contain no call at all).
static inline __attribute__((always_inline)) bool wide_query(const bvh *b, const ray *r, hit *h, bool any, bool simd,
                                                             bool generic) {
    hit best = bvh_no_hit(r);
    if (!wide_run(b, r, &best, HIT_NO_INSTANCE, any, simd, generic)) return false;
    if (!any) *h = best;
    return true;
}

static bool closest_spheres(const bvh *b, const ray *r, hit *h) { return wide_query(b, r, h, false, BVH_SIMD, false); }
static bool closest_generic(const bvh *b, const ray *r, hit *h) { return wide_query(b, r, h, false, BVH_SIMD, true); }
static bool any_spheres(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, false);
}
static bool any_generic(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, BVH_SIMD, true);
}

bool bvh_intersect_scalar(const bvh *b, const ray *r, hit *h) { return wide_query(b, r, h, false, false, true); }

bool bvh_occluded_scalar(const bvh *b, const ray *r) {
    hit h;
    return wide_query(b, r, &h, true, false, true);
}

bool bvh_intersect(const bvh *b, const ray *r, hit *h) {
    return b->spheres_only ? closest_spheres(b, r, h) : closest_generic(b, r, h);
}

bool bvh_occluded(const bvh *b, const ray *r) { return b->spheres_only ? any_spheres(b, r) : any_generic(b, r); }

void bvh_intersect2(const bvh *b, const ray *r0, const ray *r1, hit *h0, hit *h1, bool *f0, bool *f1) {
#if BVH_SIMD
    *f0 = *f1 = false;
    if (b->root == BVH_EMPTY && b->front == BVH_EMPTY) return;
    simd_ray sr0, sr1;
    bool ok0 = simd_setup(r0, &sr0), ok1 = simd_setup(r1, &sr1);
    if (!ok0 || !ok1) {
        // A NaN ray ends at once; the other goes alone.
        if (ok0) *f0 = bvh_intersect(b, r0, h0);
        if (ok1) *f1 = bvh_intersect(b, r1, h1);
        return;
    }
    stack_entry stack0[WIDE_STACK], stack1[WIDE_STACK];
    tri_cache tc0 = {.ready = false}, tc1 = {.ready = false};
    hit best0 = bvh_no_hit(r0), best1 = bvh_no_hit(r1);
    walk w0 = {b->root, 0}, w1 = {b->root, 0};
    bool found0 = false, found1 = false;
    // Alternate single steps of the two rays: two independent dependency chains in flight at once.
    int s0 = b->root == BVH_EMPTY ? STEP_DONE : STEP_MORE, s1 = s0;
    while (s0 == STEP_MORE && s1 == STEP_MORE) {
        s0 = wide_step(b, r0, NULL, &sr0, &tc0, stack0, &w0, &best0, HIT_NO_INSTANCE, &found0, false, true, true);
        s1 = wide_step(b, r1, NULL, &sr1, &tc1, stack1, &w1, &best1, HIT_NO_INSTANCE, &found1, false, true, true);
    }
    while (s0 == STEP_MORE)
        s0 = wide_step(b, r0, NULL, &sr0, &tc0, stack0, &w0, &best0, HIT_NO_INSTANCE, &found0, false, true, true);
    while (s1 == STEP_MORE)
        s1 = wide_step(b, r1, NULL, &sr1, &tc1, stack1, &w1, &best1, HIT_NO_INSTANCE, &found1, false, true, true);
    if (b->front != BVH_EMPTY) { // the huge spheres after the tree, as in wide_run
        found0 = leaf_simd(b, b->front, r0, &sr0, &tc0, &best0, HIT_NO_INSTANCE, false, true) || found0;
        found1 = leaf_simd(b, b->front, r1, &sr1, &tc1, &best1, HIT_NO_INSTANCE, false, true) || found1;
    }
    if ((*f0 = found0)) *h0 = best0;
    if ((*f1 = found1)) *h1 = best1;
#else
    *f0 = bvh_intersect(b, r0, h0);
    *f1 = bvh_intersect(b, r1, h1);
#endif
}

/* ------------------------------------------------------------------------------------------------ */
/* Brute force                                                                                        */

// Every primitive of in, in the same order of precedence as the BVHs (bvh_better).
static bool brute_run(const bvh_input *in, const ray *r, hit *best, bool any) {
    if (ray_is_nan(r)) return false;
    tri_cache tc = {.ready = false};
    bool found = false;
    for (size_t i = 0; i < in->sphere_count; i++) {
        float t;
        if (!sphere_intersect(in->spheres[i].center, in->spheres[i].radius, r, r->tmin, r->tmax, &t)) continue;
        if (any) return true;
        found = true;
        offer(best, (hit){t, (uint32_t)i, HIT_SPHERE, HIT_NO_INSTANCE, 0.0f, 0.0f});
    }
    for (size_t i = 0; i < in->quad_count; i++) {
        quad_hit qh;
        if (!quad_intersect(&in->quads[i], tri_for(&tc, r), r->tmin, r->tmax, &qh)) continue;
        if (any) return true;
        found = true;
        offer(best, (hit){qh.t, (uint32_t)i, HIT_QUAD, HIT_NO_INSTANCE, qh.alpha, qh.beta});
    }
    for (size_t i = 0; i < in->instance_count; i++) {
        const instance *inst = &in->instances[i];
        ray o = mat4_apply_ray(&inst->xf.inv, r);
        if (inst->kind == INSTANCE_SPHERE) {
            const sphere *sp = &in->instance_spheres[inst->index];
            float t;
            if (!sphere_intersect(sp->center, sp->radius, &o, o.tmin, o.tmax, &t)) continue;
            if (any) return true;
            found = true;
            offer(best, (hit){t, inst->index, HIT_SPHERE, (uint32_t)i, 0.0f, 0.0f});
            continue;
        }
        const mesh *m = &in->meshes[inst->index].geometry;
        tri_ray otr = tri_ray_make(&o);
        for (size_t k = 0; k < m->triangle_count; k++) {
            tri_hit th;
            if (!mesh_intersect_triangle(m, k, &otr, o.tmin, o.tmax, &th)) continue;
            if (any) return true;
            found = true;
            offer(best, (hit){th.t, (uint32_t)k, HIT_TRIANGLE, (uint32_t)i, th.b1, th.b2});
        }
    }
    return found;
}

bool bvh_brute_intersect(const bvh_input *in, const ray *r, hit *h) {
    hit best = bvh_no_hit(r);
    if (!brute_run(in, r, &best, false)) return false;
    *h = best;
    return true;
}

bool bvh_brute_occluded(const bvh_input *in, const ray *r) {
    hit best = bvh_no_hit(r);
    return brute_run(in, r, &best, true);
}
