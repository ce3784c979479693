// bvh_sah.c — the serial binned-SAH construction of the binary BVH (bvh_build_range) and its pieces that the
// parallel build (bvh_build_parallel.c) shares to make the same tree: range bounds, binning, the best split; and
// the build's traced steps. It calls no other file of the build: every other step calls down into it.
#include "accel/bvh_sah.h"
#include "core/trace.h"

// Grows *bounds and *cbounds by the boxes and the centroids of prims[begin, end), in index order. box_grow
// keeps the later of two equal bounds (+0 and -0 compare equal), so growing the results of consecutive chunks
// in their order gives the bits of one pass over the whole range: what the parallel build relies on.
#if defined(__SSE__)
/// A box and a centroid box being grown in registers (bvh_range_bounds, partition).
typedef struct bounds_acc {
    __m128 lo, hi, clo, chi;
} bounds_acc;

// Grows acc by box p and its centroid (centroid()'s expression), with box_grow's operand order: the later of
// two equal bounds is kept.
static inline void bounds_acc_grow(bounds_acc *acc, const box3 *p) {
    const __m128 half = _mm_set1_ps(0.5f);
    __m128 plo = _mm_load_ps(p->lo), phi = _mm_load_ps(p->hi);
    __m128 c = _mm_add_ps(_mm_mul_ps(half, plo), _mm_mul_ps(half, phi));
    acc->lo = _mm_min_ps(acc->lo, plo);
    acc->hi = _mm_max_ps(acc->hi, phi);
    acc->clo = _mm_min_ps(acc->clo, c);
    acc->chi = _mm_max_ps(acc->chi, c);
}
#endif

#if defined(__SSE__)
void bvh_range_bounds(const build_prim *prims, size_t begin, size_t end, box3 *bounds, box3 *cbounds) {
    // In registers: through the pointers every step would store and reload them (prims may alias them).
    bounds_acc acc = {_mm_load_ps(bounds->lo), _mm_load_ps(bounds->hi), _mm_load_ps(cbounds->lo),
                      _mm_load_ps(cbounds->hi)};
    for (size_t i = begin; i < end; i++) bounds_acc_grow(&acc, &prims[i].box);
    _mm_store_ps(bounds->lo, acc.lo);
    _mm_store_ps(bounds->hi, acc.hi);
    _mm_store_ps(cbounds->lo, acc.clo);
    _mm_store_ps(cbounds->hi, acc.chi);
}
#else
void bvh_range_bounds(const build_prim *prims, size_t begin, size_t end, box3 *bounds, box3 *cbounds) {
    for (size_t i = begin; i < end; i++) {
        box_grow(bounds, &prims[i].box);
        float cx = centroid(&prims[i], 0), cy = centroid(&prims[i], 1), cz = centroid(&prims[i], 2);
        box3 c = {{cx, cy, cz, 0.0f}, {cx, cy, cz, 0.0f}};
        box_grow(cbounds, &c);
    }
}
#endif

// Empty bins over the centroid box of n primitives. Ranges below about 560 primitives use fewer than SAH_BINS,
// about one per 20 (at least 8; one per primitive up to 8), as Embree's binner does: their trees trace as
// fast (1.1M bunny, bunny, rtiow-final: `bench/ab.sh`), and the 1.1M bunny's binary tree builds in 329 ms,
// not 363 (one thread).
void bvh_bins_init(bins *b, size_t n, const box3 *cbounds) {
    size_t want = n <= 8 ? (n < 4 ? 4 : n) : (n < 80 ? 8 : 4 + n / 20);
    int nb = want < SAH_BINS ? (int)want : SAH_BINS;
    b->nb = nb;
    for (int a = 0; a < 3; a++) {
        float extent = cbounds->hi[a] - cbounds->lo[a];
        b->lo[a] = cbounds->lo[a];
        b->live[a] = extent > 0.0f;
        b->scale[a] = b->live[a] ? (float)nb * (1.0f - 0x1p-20f) / extent : 0.0f;
        for (int k = 0; k < nb; k++) {
            b->box[a][k] = box_empty();
            b->count[a][k] = 0;
        }
    }
}

#if defined(__SSE4_1__)
// Bins prims[begin, end) on all three axes in one pass: the three axes' bins at once, bin_of's operations lane by
// lane (centroid, subtract, scale, truncate, clamp).
void bvh_bins_add(bins *b, const build_prim *prims, size_t begin, size_t end) {
    // Locals: the stores into the bin boxes could alias the float fields of *b.
    int nb = b->nb;
    const __m128 lo4 = _mm_setr_ps(b->lo[0], b->lo[1], b->lo[2], 0.0f), half = _mm_set1_ps(0.5f);
    const __m128 scale4 = _mm_setr_ps(b->scale[0], b->scale[1], b->scale[2], 0.0f);
    const __m128i top = _mm_set1_epi32(nb - 1), zero = _mm_setzero_si128();
    for (size_t i = begin; i < end; i++) {
        const build_prim *p = &prims[i];
        __m128 plo = _mm_load_ps(p->box.lo), phi = _mm_load_ps(p->box.hi);
        __m128 c = _mm_add_ps(_mm_mul_ps(half, plo), _mm_mul_ps(half, phi));
        __m128i k = _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(c, lo4), scale4));
        k = _mm_min_epi32(_mm_max_epi32(k, zero), top);
        int k0 = _mm_cvtsi128_si32(k), k1 = _mm_extract_epi32(k, 1), k2 = _mm_extract_epi32(k, 2);
        b->count[0][k0]++;
        box_grow(&b->box[0][k0], &p->box);
        b->count[1][k1]++;
        box_grow(&b->box[1][k1], &p->box);
        b->count[2][k2]++;
        box_grow(&b->box[2][k2], &p->box);
    }
}
#else
// Bins prims[begin, end) on all three axes in one pass.
void bvh_bins_add(bins *b, const build_prim *prims, size_t begin, size_t end) {
    // Locals: the stores into the bin boxes could alias the float fields of *b.
    int nb = b->nb;
    float lo[3] = {b->lo[0], b->lo[1], b->lo[2]}, scale[3] = {b->scale[0], b->scale[1], b->scale[2]};
    for (size_t i = begin; i < end; i++) {
        const build_prim *p = &prims[i];
        for (int a = 0; a < 3; a++) {
            int k = bin_of(centroid(p, a), lo[a], scale[a], nb);
            b->count[a][k]++;
            box_grow(&b->box[a][k], &p->box);
        }
    }
}
#endif

// The best binned SAH split over the three axes (axes with no extent are skipped).
split bvh_best_split(const builder *bd, const bins *b, const box3 *bounds) {
    split best = {-1, 0, INFINITY};
    float parent_area = box_half_area(bounds), inv_area = parent_area > 0.0f ? 1.0f / parent_area : 1.0f;
    int nb = b->nb;
    for (int a = 0; a < 3; a++) {
        if (!b->live[a]) continue;
        // Sweep from the right for the areas and counts of every right side.
        float right_area[SAH_BINS];
        size_t right_count[SAH_BINS];
        box3 acc = box_empty();
        size_t cnt = 0;
        for (int k = nb - 1; k > 0; k--) {
            box_grow(&acc, &b->box[a][k]);
            cnt += b->count[a][k];
            right_area[k] = box_half_area(&acc);
            right_count[k] = cnt;
        }
        acc = box_empty();
        cnt = 0;
        for (int k = 0; k < nb - 1; k++) {
            box_grow(&acc, &b->box[a][k]);
            cnt += b->count[a][k];
            if (cnt == 0 || right_count[k + 1] == 0) continue;
            float cost = SAH_TRAVERSAL_COST + SAH_INTERSECT_COST * inv_area *
                                                  (box_half_area(&acc) * leaf_blocks(bd, cnt) +
                                                   right_area[k + 1] * leaf_blocks(bd, right_count[k + 1]));
            if (cost < best.cost) best = (split){a, k, cost};
        }
    }
    return best;
}

// The order bvh_partition leaves is the leaf order of the tree; parallel_partition reproduces it. The boxes of the two
// sides are grown as each primitive is placed: the children need not read their primitives again for them
// (bvh_range_bounds).
#if defined(__SSE__)
size_t bvh_partition(build_prim *prims, size_t begin, size_t end, const bins *b, split s, box3 side[2],
                        box3 cside[2]) {
    // The chosen bin, recomputed with exactly the arithmetic of the binning.
    int a = s.axis, nb = b->nb;
    float lo = b->lo[a], scale = b->scale[a];
    size_t i = begin, j = end;
    // In registers, as bvh_range_bounds, from box_empty().
    box3 e = box_empty();
    bounds_acc acc[2];
    acc[0] = acc[1] = (bounds_acc){_mm_load_ps(e.lo), _mm_load_ps(e.hi), _mm_load_ps(e.lo), _mm_load_ps(e.hi)};
    while (i < j) {
        if (bin_of(centroid(&prims[i], a), lo, scale, nb) <= s.bin) {
            bounds_acc_grow(&acc[0], &prims[i].box);
            i++;
        } else {
            build_prim tmp = prims[i];
            prims[i] = prims[--j];
            prims[j] = tmp;
            bounds_acc_grow(&acc[1], &tmp.box);
        }
    }
    for (int k = 0; k < 2; k++) {
        _mm_store_ps(side[k].lo, acc[k].lo);
        _mm_store_ps(side[k].hi, acc[k].hi);
        _mm_store_ps(cside[k].lo, acc[k].clo);
        _mm_store_ps(cside[k].hi, acc[k].chi);
    }
    return i;
}
#else
size_t bvh_partition(build_prim *prims, size_t begin, size_t end, const bins *b, split s, box3 side[2],
                        box3 cside[2]) {
    // The chosen bin, recomputed with exactly the arithmetic of the binning.
    int a = s.axis, nb = b->nb;
    float lo = b->lo[a], scale = b->scale[a];
    size_t i = begin, j = end;
    side[0] = side[1] = cside[0] = cside[1] = box_empty();
    while (i < j) {
        size_t k = i;
        if (bin_of(centroid(&prims[i], a), lo, scale, nb) <= s.bin) {
            i++;
        } else {
            build_prim tmp = prims[i];
            prims[i] = prims[--j];
            prims[j] = tmp;
            k = j;
        }
        int to = k == j ? 1 : 0;
        bvh_range_bounds(prims, k, k + 1, &side[to], &cside[to]);
    }
    return i;
}
#endif

// Recursively builds the subtree over prims[begin, end) and returns its node index (depth-first order). Its
// primitives' box and centroid box are `known` ([0] and [1]) when the parent's partition grew them, else NULL.
uint32_t bvh_build_range(builder *bd, size_t begin, size_t end, uint64_t depth, const box3 *known) {
    uint32_t id = bvh_new_node(bd);
    if (depth + 1 > bd->depth) bd->depth = depth + 1;
    box3 bounds = box_empty(), cbounds = box_empty();
    if (known) {
        bounds = known[0];
        cbounds = known[1];
    } else {
        bvh_range_bounds(bd->prims, begin, end, &bounds, &cbounds);
    }
    box_canonical(&bounds);
    box_canonical(&cbounds);
    bvh2_node *node = &bd->nodes[id];
    node_set_box(node, &bounds);
    size_t n = end - begin;
    bool stopped = stop_requested(bd);
    split s = {-1, 0, INFINITY};
    bins b;
    if (!stopped && n > 1 && depth + 1 < BVH_MAX_DEPTH) {
        bvh_bins_init(&b, n, &cbounds);
        bvh_bins_add(&b, bd->prims, begin, end);
        s = bvh_best_split(bd, &b, &bounds);
    }
    if (stopped || keep_leaf(bd, bd->prims, begin, n, depth, s.cost)) {
        node_set_leaf(bd, node, begin, n);
        return id;
    }
    // No axis separates the centroids when they all coincide: halve the range.
    box3 side[2], cside[2];
    if (s.axis < 0) {
        size_t mid = begin + n / 2;
        bvh_build_range(bd, begin, mid, depth + 1, NULL);
        uint32_t right = bvh_build_range(bd, mid, end, depth + 1, NULL);
        bd->nodes[id].offset = right;
        bd->nodes[id].count = 0;
        return id;
    }
    size_t mid = bvh_partition(bd->prims, begin, end, &b, s, side, cside);
    bvh_build_range(bd, begin, mid, depth + 1, (const box3[2]){side[0], cside[0]});
    uint32_t right = bvh_build_range(bd, mid, end, depth + 1, (const box3[2]){side[1], cside[1]});
    bd->nodes[id].offset = right;
    bd->nodes[id].count = 0;
    return id;
}

/* ------------------------------------------------------------------------------------------------ */
/* The build's traced steps                                                                           */

int64_t bvh_step_began(void) { return trace_current() ? trace_clock() : 0; }

void bvh_step_traced(const char *name, int64_t began) {
    trace_lane *lane = trace_current();
    if (lane) trace_add(lane, &(trace_event){name, "render", began, trace_clock(), 0, {{0}}});
}
