// bvh_packet.c — closest hits of up to 16 coherent rays (a pixel's camera rays) through a wide BVH of triangles,
// traversed as one packet: one interval-arithmetic box test of a node for the whole packet, and each leaf tested by
// every ray that may still find a nearer hit there, all rays at once when they share their ray-space axes
// (leaf_rays) or one by one with the single-ray leaf test (leaf_simd). The hits are bvh_intersect's. The packet
// kernels are AVX2 (BVH_SIMD) only; otherwise the rays go one by one.
#include "accel/bvh_wide.h"

#if BVH_SIMD
/// A packet of coherent rays (directions of one sign per axis) bounded for box tests: the range of their origins
/// and of their inverse directions on each axis, broadcast.
typedef struct packet_bounds {
    __m256 olo[3], ohi[3], ilo[3], ihi[3];
    bool neg[3]; ///< the directions point down the axis: a box is entered by its upper plane
    float tmin;  ///< the smallest of the rays' tmin
} packet_bounds;

/// A packet's rays are set up and tested in groups of eight, the lanes of an AVX register.
enum { PACKET_GROUP = 8 };
_Static_assert(sizeof(pk) == sizeof(__m256), "a group is one SIMD packet wide (edges_zero, edges_mixed)");
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
                        : p->h.instance == HIT_NO_INSTANCE ? b->input.mesh
                                                           : b->input.flat[p->h.instance];
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
                unsigned exact = (unsigned)_mm256_movemask_ps(edges_zero(u, v, w)) & group;
                unsigned inside = ~edges_mixed(u, v, w) & group & ~exact;
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
#else
bool bvh_coherent(const bvh *b) {
    (void)b;
    return false;
}

void bvh_intersect_coherent(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
}
#endif
