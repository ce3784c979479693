// bvh_simd.h — the AVX2 + FMA kernels of the wide BVH (private to src/accel): the ray broadcast into
// registers, eight box tests at once, and packets of spheres and of triangles at once, each lane bit-identical
// to the scalar test. Included only where BVH_SIMD is 1.
#ifndef GLINT_BVH_SIMD_H
#define GLINT_BVH_SIMD_H

#include "accel/bvh_kernel.h"

#include <immintrin.h>

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
// retire (no store-to-load forwarding), so every load here reads one float. `boxes_only`: only what the box
// tests read (a tree of triangles, whose constants are simd_tri's), where a stream's rays would store the rest
// for nothing.
static inline bool simd_setup(const ray *r, simd_ray *s, bool boxes_only) {
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
    s->tmin = PK(broadcast_ss)(&r->tmin);
    if (boxes_only) return true;
    s->ox = PK(broadcast_ss)(&r->o.x);
    s->oy = PK(broadcast_ss)(&r->o.y);
    s->oz = PK(broadcast_ss)(&r->o.z);
    s->dx = PK(broadcast_ss)(&r->d.x);
    s->dy = PK(broadcast_ss)(&r->d.y);
    s->dz = PK(broadcast_ss)(&r->d.z);
    s->tmax = PK(broadcast_ss)(&r->tmax);
    float a = v3_dot(r->d, r->d);
    s->a = PK(set1_ps)(a);
    s->inv_a = PK(set1_ps)(1.0f / a);
    s->tmin_nonneg = PK(cmp_ps)(s->tmin, PK(setzero_ps)(), _CMP_GE_OQ);
    return true;
}

/// v's lanes with n added to their bits: n units in their last place up, for the non-negative distances of the box
/// tests (SLAB_FAR_ULPS).
static inline __m256 ulps_up(__m256 v, int n) {
    return _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(v), _mm256_set1_epi32(n)));
}

static inline unsigned wnode_test_simd(const bvh_wnode *n, const simd_ray *s, float tlimit, bool ties, float *tnear) {
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
    // slab_exit: the exit widened by SLAB_FAR_ULPS after the cap by the best hit where ties count (closest hits),
    // before it otherwise (bvh_kernel.h); then tn <= exit compared as integers, tn < exit + 1.
    __m256 tf = _mm256_min_ps(_mm256_min_ps(fx, fy), fz), cap = _mm256_set1_ps(tlimit);
    _mm256_storeu_ps(tnear, tn);
    __m256 exit = ties ? ulps_up(_mm256_min_ps(tf, cap), SLAB_FAR_ULPS) : _mm256_min_ps(ulps_up(tf, SLAB_FAR_ULPS), cap);
    __m256i entered = _mm256_cmpgt_epi32(_mm256_castps_si256(ulps_up(exit, 1)), _mm256_castps_si256(tn));
    return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(entered));
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

// tri_intersect itself for ray tr and triangle (v0, v1, v2), its hit written into lane l of t, b1, b2: for the
// lanes of a SIMD test with an edge function rounded to zero, which tri_intersect redoes in double.
static inline bool exact_lane(const tri_ray *tr, vec3 v0, vec3 v1, vec3 v2, float tmin, float tmax, int l, float *t,
                              float *b1, float *b2) {
    tri_hit th;
    if (!tri_intersect(tr, v0, v1, v2, tmin, tmax, &th)) return false;
    t[l] = th.t;
    b1[l] = th.b1;
    b2[l] = th.b2;
    return true;
}

// The lanes of triangle packet p that tri_intersect tests in double (an edge function rounded to zero): each
// through tri_intersect itself, its result written into lane k of t, b1, b2. Returns the lanes hit.
static __attribute__((noinline)) unsigned triangles_exact(const bvh_triangle_packet *p, const tri_ray *tr, float tmin,
                                                          float tmax, unsigned lanes, float *t, float *b1, float *b2) {
    unsigned found = 0;
    do {
        int k = __builtin_ctz(lanes);
        lanes &= lanes - 1;
        vec3 v[3];
        for (int j = 0; j < 3; j++) v[j] = v3(p->v[j][0][k], p->v[j][1][k], p->v[j][2][k]);
        if (exact_lane(tr, v[0], v[1], v[2], tmin, tmax, k, t, b1, b2)) found |= 1u << k;
    } while (lanes);
    return found;
}

/// A ray's triangle-test constants (tri_ray) broadcast into registers, made once per ray.
typedef struct simd_tri {
    pk ox, oy, oz, sx, sy, sz, tmin, tmax; ///< origin and shear in ray-space order (x = kx, ...)
    int kx, ky, kz;
    float tmin1, tmax1;
    const tri_ray *tr; ///< for the lanes that take tri_intersect's double path
} simd_tri;

static inline void simd_tri_setup(const tri_ray *tr, float tmin, float tmax, simd_tri *st) {
    const float o[3] = {tr->o.x, tr->o.y, tr->o.z};
    st->ox = PK(set1_ps)(o[tr->kx]);
    st->oy = PK(set1_ps)(o[tr->ky]);
    st->oz = PK(set1_ps)(o[tr->kz]);
    st->sx = PK(set1_ps)(tr->sx);
    st->sy = PK(set1_ps)(tr->sy);
    st->sz = PK(set1_ps)(tr->sz);
    st->tmin = PK(set1_ps)(tmin);
    st->tmax = PK(set1_ps)(tmax);
    st->kx = tr->kx;
    st->ky = tr->ky;
    st->kz = tr->kz;
    st->tmin1 = tmin;
    st->tmax1 = tmax;
    st->tr = tr;
}

/// The lanes with an edge function of zero, all bits set: tri_intersect decides them in double (triangles_exact).
static inline pk edges_zero(pk u, pk v, pk w) {
    const pk zero = PK(setzero_ps)();
    return PK(or_ps)(PK(or_ps)(PK(cmp_ps)(u, zero, _CMP_EQ_OQ), PK(cmp_ps)(v, zero, _CMP_EQ_OQ)),
                     PK(cmp_ps)(w, zero, _CMP_EQ_OQ));
}

/// The lanes whose edge functions u, v, w have both signs: the ray passes beside the triangle. Read off the sign bits
/// (two fewer instructions per edge than comparisons): the signs differ where the OR of the three has its sign bit
/// and the AND does not. Meaningful on lanes with no edge function zero or NaN (those with a zero take the exact
/// path; a NaN lane, unused, fails the determinant's test whichever way it falls here).
static inline unsigned edges_mixed(pk u, pk v, pk w) {
    return (unsigned)PK(movemask_ps)(PK(xor_ps)(PK(or_ps)(PK(or_ps)(u, v), w), PK(and_ps)(PK(and_ps)(u, v), w)));
}

// A packet of triangles at once, each lane computing exactly what tri_intersect computes for it (the same
// float operations in the same order, unfused), so t and the barycentrics are bit-identical to the scalar test
// (the camera packets' leaf_rays computes the same with the roles of the lanes turned round);
// lanes with an edge function of zero go through tri_intersect's double path. Returns the mask of lanes hit with
// tmin < t < tmax, with t, b1, b2 in the arrays (lanes outside the mask undefined).
static inline unsigned triangles_simd(const bvh_triangle_packet *p, const simd_tri *st, float *t, float *b1,
                                      float *b2) {
    pk x[3], y[3], z[3];
    for (int j = 0; j < 3; j++) { // vertex j - o, sheared: x - sx z, y - sy z (products, then differences)
        z[j] = PK(sub_ps)(PK(load_ps)(p->v[j][st->kz]), st->oz);
        x[j] = PK(sub_ps)(PK(sub_ps)(PK(load_ps)(p->v[j][st->kx]), st->ox), PK(mul_ps)(st->sx, z[j]));
        y[j] = PK(sub_ps)(PK(sub_ps)(PK(load_ps)(p->v[j][st->ky]), st->oy), PK(mul_ps)(st->sy, z[j]));
    }
    pk u = PK(sub_ps)(PK(mul_ps)(x[2], y[1]), PK(mul_ps)(y[2], x[1]));
    pk v = PK(sub_ps)(PK(mul_ps)(x[0], y[2]), PK(mul_ps)(y[0], x[2]));
    pk w = PK(sub_ps)(PK(mul_ps)(x[1], y[0]), PK(mul_ps)(y[1], x[0]));
    const pk zero = PK(setzero_ps)();
    unsigned exact = (unsigned)PK(movemask_ps)(edges_zero(u, v, w));
    // Edges of both signs: outside (most lanes of most packets, so most calls end here, before the division).
    unsigned inside = ~edges_mixed(u, v, w) & ((1u << BVH_PACKET) - 1) & ~exact;
    unsigned mask = 0;
    if (inside) {
        pk det = PK(add_ps)(PK(add_ps)(u, v), w);
        pk scaled = PK(mul_ps)(
            PK(add_ps)(PK(add_ps)(PK(mul_ps)(u, z[0]), PK(mul_ps)(v, z[1])), PK(mul_ps)(w, z[2])),
            st->sz);
        pk inv = PK(div_ps)(PK(set1_ps)(1.0f), det);
        pk tv = PK(mul_ps)(scaled, inv);
        // det zero or NaN (unused lanes are NaN), and t outside (tmin, tmax), fail these ordered comparisons.
        pk ok = PK(and_ps)(PK(cmp_ps)(det, zero, _CMP_NEQ_OQ),
                                  PK(and_ps)(PK(cmp_ps)(tv, st->tmin, _CMP_GT_OQ),
                                                PK(cmp_ps)(tv, st->tmax, _CMP_LT_OQ)));
        mask = inside & (unsigned)PK(movemask_ps)(ok);
        if (mask) {
            PK(store_ps)(t, tv);
            PK(store_ps)(b1, PK(mul_ps)(v, inv));
            PK(store_ps)(b2, PK(mul_ps)(w, inv));
        }
    }
    if (exact) mask |= triangles_exact(p, st->tr, st->tmin1, st->tmax1, exact, t, b1, b2);
    return mask;
}

#endif
