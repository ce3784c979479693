// bvh_build.c — binned-SAH construction of the binary BVH, and its collapse into the wide BVH with
// structure-of-arrays leaf packets.
#include "accel/bvh.h"
#include "accel/tri_split.h"
#include "core/array.h"
#include "core/thread_pool.h"
#include "core/trace.h"

#include <stdatomic.h>

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#if defined(__SSE4_1__)
#include <smmintrin.h>
#elif defined(__SSE__)
#include <xmmintrin.h>
#endif

enum { SAH_BINS = 32 };

_Static_assert(sizeof(bvh_packet_header) == sizeof(bvh_slot), "a packet's header is one slot");
_Static_assert(sizeof(bvh_sphere_packet) % sizeof(bvh_slot) == 0, "a packet is a whole number of slots");
_Static_assert(offsetof(bvh_sphere_packet, cx) % (BVH_PACKET * sizeof(float)) == 0, "lanes aligned for SIMD loads");
_Static_assert(sizeof(bvh_triangle_packet) % sizeof(bvh_slot) == 0, "a packet is a whole number of slots");
_Static_assert(offsetof(bvh_triangle_packet, v) % (BVH_PACKET * sizeof(float)) == 0, "lanes aligned for SIMD loads");

// SAH constants: the cost of visiting a node relative to testing one leaf packet (wide BVH) or one
// primitive (binary BVH). Halving or doubling either changed rtiow-final by less than the noise (1%).
static const float SAH_TRAVERSAL_COST = 1.0f;
static const float SAH_INTERSECT_COST = 1.0f;
// Largest leaf of the binary BVH (its leaves are tested one primitive at a time).
enum { BIN_MAX_LEAF = 4 };

/// Axis-aligned box; the fourth lanes are zero padding so that a box is two SSE registers.
typedef struct box3 {
    _Alignas(16) float lo[4];
    float hi[4];
} box3;

static box3 box_empty(void) {
    box3 b = {{INFINITY, INFINITY, INFINITY, 0.0f}, {-INFINITY, -INFINITY, -INFINITY, 0.0f}};
    return b;
}

// min/max as comparisons: fminf/fmaxf are library calls without -ffast-math, and bounds hold no NaN.
#if !defined(__SSE__)
static inline float min2(float a, float b) { return a < b ? a : b; }
#endif
static inline float max2(float a, float b) { return a > b ? a : b; }

static inline void box_grow(box3 *b, const box3 *o) {
#if defined(__SSE__)
    _mm_store_ps(b->lo, _mm_min_ps(_mm_load_ps(b->lo), _mm_load_ps(o->lo)));
    _mm_store_ps(b->hi, _mm_max_ps(_mm_load_ps(b->hi), _mm_load_ps(o->hi)));
#else
    for (int a = 0; a < 4; a++) {
        b->lo[a] = min2(b->lo[a], o->lo[a]);
        b->hi[a] = max2(b->hi[a], o->hi[a]);
    }
#endif
}

static float box_half_area(const box3 *b) {
#if defined(__SSE__)
    // The scalar expression below lane by lane: (dx dy, dy dz, dz dx), summed in that order.
    __m128 d = _mm_sub_ps(_mm_load_ps(b->hi), _mm_load_ps(b->lo));
    __m128 ok = _mm_cmpge_ps(d, _mm_setzero_ps());
    if ((_mm_movemask_ps(ok) & 7) != 7) return 0.0f;
    __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));
    __m128 sum = _mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, _MM_SHUFFLE(3, 2, 1, 1))),
                            _mm_shuffle_ps(p, p, _MM_SHUFFLE(3, 2, 1, 2)));
    return _mm_cvtss_f32(sum);
#else
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    if (!(dx >= 0.0f && dy >= 0.0f && dz >= 0.0f)) return 0.0f;
    return dx * dy + dy * dz + dz * dx;
#endif
}

/// Per-primitive build input: padded bounds and reference (48 bytes: the build's largest array).
typedef struct build_prim {
    box3 box;
    prim_ref ref;
    uint32_t split_levels; ///< a triangle's tri_split_levels, found while its corners are at hand (gather)
} build_prim;

/// Centroid of a primitive's box on axis a, computed where it is needed rather than stored (16 bytes a
/// primitive of peak memory), with the same expression everywhere.
static inline float centroid(const build_prim *p, int a) { return 0.5f * p->box.lo[a] + 0.5f * p->box.hi[a]; }

typedef struct builder {
    build_prim *prims;  ///< permuted in place into leaf order
    bvh2_node *nodes;
    size_t node_count;
    int block_shift;    ///< log2 of the primitives tested together in a leaf (SAH counts leaf cost in blocks)
    size_t block_mask;  ///< (1 << block_shift) - 1
    int max_leaf;       ///< largest leaf the SAH may choose (deeper than BVH_MAX_DEPTH forces a leaf)
    uint64_t depth, leaves;
    const atomic_int *stop; ///< nonzero once a stop is requested (NULL: never): the build gives up
    bool stopped;
} builder;

// Padding that keeps a box conservative after float rounding of the centre, radius and the slab test.
static box3 sphere_box(const sphere *s) {
    float r = fabsf(s->radius);
    float m = max2(fabsf(s->center.x), max2(fabsf(s->center.y), fabsf(s->center.z)));
    float pad = (m + r) * 0x1p-19f + 0x1p-100f;
    box3 b = box_empty();
    b.lo[0] = s->center.x - r - pad;
    b.lo[1] = s->center.y - r - pad;
    b.lo[2] = s->center.z - r - pad;
    b.hi[0] = s->center.x + r + pad;
    b.hi[1] = s->center.y + r + pad;
    b.hi[2] = s->center.z + r + pad;
    return b;
}

// Bin of a centroid coordinate; the same arithmetic when binning and when partitioning.
static inline int bin_of(float c, float lo, float scale, int bins) {
    int k = (int)((c - lo) * scale);
    return k < 0 ? 0 : (k >= bins ? bins - 1 : k);
}

static float leaf_blocks(const builder *bd, size_t n) { return (float)((n + bd->block_mask) >> bd->block_shift); }

static uint32_t new_node(builder *bd) { return (uint32_t)bd->node_count++; }

// Grows *bounds and *cbounds by the boxes and the centroids of prims[begin, end), in index order. box_grow
// keeps the later of two equal bounds (+0 and -0 compare equal), so growing the results of consecutive chunks
// in their order gives the bits of one pass over the whole range: what the parallel build relies on.
#if defined(__SSE__)
/// A box and a centroid box being grown in registers (range_bounds, partition).
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

static void range_bounds(const build_prim *prims, size_t begin, size_t end, box3 *bounds, box3 *cbounds) {
#if defined(__SSE__)
    // In registers: through the pointers every step would store and reload them (prims may alias them).
    bounds_acc acc = {_mm_load_ps(bounds->lo), _mm_load_ps(bounds->hi), _mm_load_ps(cbounds->lo),
                      _mm_load_ps(cbounds->hi)};
    for (size_t i = begin; i < end; i++) bounds_acc_grow(&acc, &prims[i].box);
    _mm_store_ps(bounds->lo, acc.lo);
    _mm_store_ps(bounds->hi, acc.hi);
    _mm_store_ps(cbounds->lo, acc.clo);
    _mm_store_ps(cbounds->hi, acc.chi);
#else
    for (size_t i = begin; i < end; i++) {
        box_grow(bounds, &prims[i].box);
        float cx = centroid(&prims[i], 0), cy = centroid(&prims[i], 1), cz = centroid(&prims[i], 2);
        box3 c = {{cx, cy, cz, 0.0f}, {cx, cy, cz, 0.0f}};
        box_grow(cbounds, &c);
    }
#endif
}

/// The SAH bins of a range: on each axis its centroid box cut into nb equal bins, each with the box and the
/// count of the primitives whose centroid falls in it.
typedef struct bins {
    int nb;
    float lo[3], scale[3];
    bool live[3]; ///< the centroids spread along the axis (one without extent is not split)
    box3 box[3][SAH_BINS];
    size_t count[3][SAH_BINS];
} bins;

// Empty bins over the centroid box of n primitives. Ranges below about 560 primitives use fewer than SAH_BINS,
// about one per 20 (at least 8; one per primitive up to 8), as Embree's binner does: their trees trace as
// fast (1.1M bunny, bunny, rtiow-final: `bench/ab.sh`), and the 1.1M bunny's binary tree builds in 329 ms,
// not 363 (one thread).
static void bins_init(bins *b, size_t n, const box3 *cbounds) {
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

// Bins prims[begin, end) on all three axes in one pass.
static void bins_add(bins *b, const build_prim *prims, size_t begin, size_t end) {
    // Locals: the stores into the bin boxes could alias the float fields of *b.
    int nb = b->nb;
#if defined(__SSE4_1__)
    // The three axes' bins at once: bin_of's operations lane by lane (centroid, subtract, scale, truncate, clamp).
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
#else
    float lo[3] = {b->lo[0], b->lo[1], b->lo[2]}, scale[3] = {b->scale[0], b->scale[1], b->scale[2]};
    for (size_t i = begin; i < end; i++) {
        const build_prim *p = &prims[i];
        for (int a = 0; a < 3; a++) {
            int k = bin_of(centroid(p, a), lo[a], scale[a], nb);
            b->count[a][k]++;
            box_grow(&b->box[a][k], &p->box);
        }
    }
#endif
}

// Adds the bins of the primitives that follow into's (the same setup) to into.
static void bins_merge(bins *into, const bins *from) {
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < into->nb; k++) {
            into->count[a][k] += from->count[a][k];
            box_grow(&into->box[a][k], &from->box[a][k]);
        }
}

/// A split of a range: the primitives in bins 0..bin of the axis go left.
typedef struct split {
    int axis; ///< -1: none (every centroid coincides, or the range was not binned)
    int bin;
    float cost;
} split;

// The best binned SAH split over the three axes (axes with no extent are skipped).
static split best_split(const builder *bd, const bins *b, const box3 *bounds) {
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

// Whether prims[begin, begin + n) are of one kind (and, flattened triangles, of one instance): one packet's worth.
static bool one_kind(const build_prim *prims, size_t begin, size_t n) {
    for (size_t i = begin + 1; i < begin + n; i++)
        if (prims[i].ref.kind != prims[begin].ref.kind || prims[i].ref.instance != prims[begin].ref.instance)
            return false;
    return true;
}

// Whether prims[begin, begin + n) at `depth` stay a leaf: one primitive, the depth limit, or a leaf of one kind that
// the SAH prefers to the best split (unless it holds too many primitives for a leaf). Kinds go to packets of their
// own, and a floor's quad in a leaf with the triangles beside it would make that leaf's box as wide as the floor
// and as high as the triangles: every ray leaving the floor would start in it and test them all.
static bool keep_leaf(const builder *bd, size_t begin, size_t n, uint64_t depth, float split_cost) {
    if (n <= 1 || depth + 1 >= BVH_MAX_DEPTH) return true;
    return n <= (size_t)bd->max_leaf && leaf_blocks(bd, n) * SAH_INTERSECT_COST <= split_cost &&
           one_kind(bd->prims, begin, n);
}

// A stop request ends the build: every range left becomes a leaf, and bvh_build discards the tree.
static bool stop_requested(builder *bd) {
    if (!bd->stopped && bd->stop && atomic_load_explicit(bd->stop, memory_order_relaxed)) bd->stopped = true;
    return bd->stopped;
}

static void node_set_box(bvh2_node *node, const box3 *b) {
    memcpy(node->box, b->lo, 3 * sizeof(float));
    memcpy(node->box + 3, b->hi, 3 * sizeof(float));
}

static void node_set_leaf(builder *bd, bvh2_node *node, size_t begin, size_t n) {
    node->offset = (uint32_t)begin;
    node->count = (uint32_t)n;
    bd->leaves++;
}

// Gives zero bounds one sign (+0): the box of a set of primitives is then the same bits whatever the order they
// were grown in, so that bounds grown during a partition equal range_bounds' (and the parallel build's).
static void box_canonical(box3 *b) {
    for (int a = 0; a < 4; a++) {
        b->lo[a] += 0.0f;
        b->hi[a] += 0.0f;
    }
}

// Partitions prims[begin, end) by the split, left side first, and returns where the right side starts. The
// order it leaves is the leaf order of the tree; parallel_partition reproduces it. side[0] and side[1] get the
// boxes and centroid boxes of the two sides, grown as each primitive is placed: the children need not read
// their primitives again for them (range_bounds).
static size_t partition(build_prim *prims, size_t begin, size_t end, const bins *b, split s, box3 side[2],
                        box3 cside[2]) {
    // The chosen bin, recomputed with exactly the arithmetic of the binning.
    int a = s.axis, nb = b->nb;
    float lo = b->lo[a], scale = b->scale[a];
    size_t i = begin, j = end;
#if defined(__SSE__)
    // In registers, as range_bounds, from box_empty().
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
#else
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
        range_bounds(prims, k, k + 1, &side[to], &cside[to]);
    }
#endif
    return i;
}

// Recursively builds the subtree over prims[begin, end) and returns its node index (depth-first order). Its
// primitives' box and centroid box are `known` ([0] and [1]) when the parent's partition grew them, else NULL.
static uint32_t build_range(builder *bd, size_t begin, size_t end, uint64_t depth, const box3 *known) {
    uint32_t id = new_node(bd);
    if (depth + 1 > bd->depth) bd->depth = depth + 1;
    box3 bounds = box_empty(), cbounds = box_empty();
    if (known) {
        bounds = known[0];
        cbounds = known[1];
    } else {
        range_bounds(bd->prims, begin, end, &bounds, &cbounds);
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
        bins_init(&b, n, &cbounds);
        bins_add(&b, bd->prims, begin, end);
        s = best_split(bd, &b, &bounds);
    }
    if (stopped || keep_leaf(bd, begin, n, depth, s.cost)) {
        node_set_leaf(bd, node, begin, n);
        return id;
    }
    // No axis separates the centroids when they all coincide: halve the range.
    box3 side[2], cside[2];
    if (s.axis < 0) {
        size_t mid = begin + n / 2;
        build_range(bd, begin, mid, depth + 1, NULL);
        uint32_t right = build_range(bd, mid, end, depth + 1, NULL);
        bd->nodes[id].offset = right;
        bd->nodes[id].count = 0;
        return id;
    }
    size_t mid = partition(bd->prims, begin, end, &b, s, side, cside);
    build_range(bd, begin, mid, depth + 1, (const box3[2]){side[0], cside[0]});
    uint32_t right = build_range(bd, mid, end, depth + 1, (const box3[2]){side[1], cside[1]});
    bd->nodes[id].offset = right;
    bd->nodes[id].count = 0;
    return id;
}

// ---- The parallel build ----
//
// It makes exactly the tree of build_range(bd, 0, n, 0), for any number of threads. Ranges of at least
// subtree_min primitives (the top of the tree, where the root alone reads every primitive) are split one
// at a time by all threads together: their bounds and bins are computed in chunks and grown together in
// chunk order (the bits of one pass: range_bounds), and parallel_partition reproduces partition's order.
// Smaller ranges are subtrees, each built by build_range on one thread into its own node buffer, largest
// first; then every subtree is copied to where the serial build numbers it, its child offsets moved along.

// Defaults: a build over fewer than 2 * PARALLEL_MIN primitives runs on one thread (threads would cost more
// than they save); the top leaves at least SUBTREES_PER_THREAD subtrees per thread, for the balance of the
// threads; a step over a range is cut into at most CHUNKS_PER_THREAD chunks per thread, of at least
// PARALLEL_MIN / CHUNK_DIVISOR primitives.
enum { PARALLEL_MIN = 1 << 15, SUBTREES_PER_THREAD = 4, CHUNKS_PER_THREAD = 4, CHUNK_DIVISOR = 8 };
#define NO_SUBTREE SIZE_MAX

/// A range the top leaves to one thread.
typedef struct subtree {
    size_t begin, end;
    uint64_t depth; ///< of its root in the whole tree
    builder bd;     ///< its build: own nodes (local indices), statistics, stop
    uint32_t base;  ///< index of its root in the node array
    bool failed;    ///< out of memory
} subtree;

/// A node of the top, or the place of a subtree, in depth-first order.
typedef struct top_node {
    bvh2_node node;
    size_t right;   ///< inner node: the top_node of its second child (the first follows it)
    size_t subtree; ///< NO_SUBTREE: a node of the top; else the subtree in this place
    uint32_t index; ///< in the node array
} top_node;

/// What one chunk of a step over a range leaves for the steps after it.
typedef struct chunk {
    box3 bounds, cbounds;  ///< of its primitives and their centroids
    size_t wrong_front;    ///< right-side primitives before the split point, then the number of the first
    size_t wrong_back;     ///< left-side primitives after it, then the number of the first (counted from the end)
    size_t segment;        ///< rotation: back_left index of the first segment start after the chunk's start
    build_prim head, next; ///< rotation: the first element of its segment and the element after the chunk
} chunk;

typedef struct par_build {
    builder proto; ///< the settings every subtree copies; the statistics and stop of the top
    thread_pool *pool;
    size_t subtree_min, grain, max_chunks;
    top_node *top;
    size_t top_count, top_cap;
    subtree *subtrees;
    size_t subtree_count, subtree_cap;
    chunk *chunks;                    ///< max_chunks
    bins *chunk_bins;                 ///< max_chunks
    unsigned char *left;              ///< the side of every primitive of the range being partitioned
    uint32_t *front_right, *back_left; ///< positions of the primitives on the wrong side, paired by number
    bool failed;                      ///< out of memory
} par_build;

/// One step over [begin, end), chunk by chunk on the pool, and the range it works for.
typedef struct range_step {
    par_build *pb;
    size_t begin, end, count; ///< `count` chunks over [begin, end)
    const bins *b;
    split s;
    size_t mid, range_end, pairs; ///< partition: the split point, the range's end, wrong-side pairs
} range_step;

static size_t chunk_begin(const range_step *st, size_t k) { return st->begin + (st->end - st->begin) * k / st->count; }

// Runs fn over [begin, end) cut into chunks of at least pb->grain elements.
static void run_chunks(par_build *pb, range_step *st, size_t begin, size_t end, thread_pool_fn fn) {
    size_t count = (end - begin) / pb->grain;
    st->begin = begin;
    st->end = end;
    st->count = count < 1 ? 1 : (count > pb->max_chunks ? pb->max_chunks : count);
    thread_pool_run(pb->pool, st->count, fn, st);
}

static void step_bounds(void *ctx, size_t k) {
    range_step *st = ctx;
    chunk *c = &st->pb->chunks[k];
    c->bounds = c->cbounds = box_empty();
    range_bounds(st->pb->proto.prims, chunk_begin(st, k), chunk_begin(st, k + 1), &c->bounds, &c->cbounds);
}

static void step_bins(void *ctx, size_t k) {
    range_step *st = ctx;
    bins *b = &st->pb->chunk_bins[k];
    *b = *st->b; // empty, with the range's setup
    bins_add(b, st->pb->proto.prims, chunk_begin(st, k), chunk_begin(st, k + 1));
}

// partition's order, computed in parallel. partition walks i up from begin; a right-side primitive at i
// is swapped with the last unseen one (at --j), which is examined next. Its result: every left-side
// primitive before the split point `mid` stays; the m-th right-side one there (from the left) swaps with
// the m-th left-side one after mid (from the right); then, after mid, each segment that starts at mid or
// at one of those left-side positions (and runs to the next, or to the end) turns left by one place.
static void step_classify(void *ctx, size_t k) {
    range_step *st = ctx;
    par_build *pb = st->pb;
    const build_prim *prims = pb->proto.prims;
    int a = st->s.axis, nb = st->b->nb, bin = st->s.bin;
    float lo = st->b->lo[a], scale = st->b->scale[a];
    size_t wrong_front = 0, wrong_back = 0;
    for (size_t i = chunk_begin(st, k), end = chunk_begin(st, k + 1); i < end; i++) {
        bool left = bin_of(centroid(&prims[i], a), lo, scale, nb) <= bin;
        pb->left[i] = left;
        if (i < st->mid) wrong_front += !left;
        else wrong_back += left;
    }
    pb->chunks[k].wrong_front = wrong_front;
    pb->chunks[k].wrong_back = wrong_back;
}

static void step_number(void *ctx, size_t k) {
    range_step *st = ctx;
    par_build *pb = st->pb;
    size_t lo = chunk_begin(st, k), hi = chunk_begin(st, k + 1), m = pb->chunks[k].wrong_front;
    for (size_t i = lo; i < hi && i < st->mid; i++)
        if (!pb->left[i]) pb->front_right[m++] = (uint32_t)i;
    m = pb->chunks[k].wrong_back;
    for (size_t i = hi; i > lo && i > st->mid;)
        if (pb->left[--i]) pb->back_left[m++] = (uint32_t)i;
}

static void step_swap(void *ctx, size_t k) {
    range_step *st = ctx;
    par_build *pb = st->pb;
    build_prim *prims = pb->proto.prims;
    for (size_t m = chunk_begin(st, k), end = chunk_begin(st, k + 1); m < end; m++) {
        build_prim tmp = prims[pb->front_right[m]];
        prims[pb->front_right[m]] = prims[pb->back_left[m]];
        prims[pb->back_left[m]] = tmp;
    }
}

// Segment starts ascend as mid, back_left[pairs - 1], ..., back_left[0]. Before the rotation writes, each
// chunk of [mid, end) saves the head of the segment it begins in and the element just after it.
static void step_save(void *ctx, size_t k) {
    range_step *st = ctx;
    par_build *pb = st->pb;
    chunk *c = &pb->chunks[k];
    size_t lo = chunk_begin(st, k), hi = chunk_begin(st, k + 1);
    // The first m with back_left[m] <= lo (back_left descends): the last segment start at or before lo.
    size_t l = 0, r = st->pairs;
    while (l < r) {
        size_t m = l + (r - l) / 2;
        if (pb->back_left[m] <= lo) r = m;
        else l = m + 1;
    }
    c->segment = l;
    c->head = pb->proto.prims[l < st->pairs ? pb->back_left[l] : st->mid];
    if (hi < st->end) c->next = pb->proto.prims[hi];
}

static void step_rotate(void *ctx, size_t k) {
    range_step *st = ctx;
    par_build *pb = st->pb;
    build_prim *prims = pb->proto.prims;
    const chunk *c = &pb->chunks[k];
    size_t m = c->segment; // back_left[m - 1]: the next segment start (none when m is 0)
    build_prim head = c->head;
    for (size_t p = chunk_begin(st, k), hi = chunk_begin(st, k + 1); p < hi; p++) {
        if (m > 0 && pb->back_left[m - 1] == p) { // a segment starts here: keep its head before it is overwritten
            head = prims[p];
            m--;
        }
        size_t q = p + 1;
        bool last = q == st->end || (m > 0 && pb->back_left[m - 1] == q);
        prims[p] = last ? head : (q < hi ? prims[q] : c->next);
    }
}

// Partitions prims[begin, end) by the split into partition's very order; returns the split point.
static size_t parallel_partition(par_build *pb, range_step *st, size_t begin, size_t end, const bins *b, split s) {
    size_t left = 0;
    for (int k = 0; k <= s.bin; k++) left += b->count[s.axis][k];
    st->b = b;
    st->s = s;
    st->mid = begin + left;
    run_chunks(pb, st, begin, end, step_classify);
    // Number the wrong-side primitives: before mid from the left, after it from the right.
    size_t front = 0, back = 0;
    for (size_t k = 0; k < st->count; k++) {
        size_t n = pb->chunks[k].wrong_front;
        pb->chunks[k].wrong_front = front;
        front += n;
    }
    for (size_t k = st->count; k-- > 0;) {
        size_t n = pb->chunks[k].wrong_back;
        pb->chunks[k].wrong_back = back;
        back += n;
    }
    st->pairs = front; // == back: as many right-side primitives before mid as left-side ones after it
    run_chunks(pb, st, begin, end, step_number);
    if (st->pairs) run_chunks(pb, st, 0, st->pairs, step_swap);
    if (st->mid < end) {
        run_chunks(pb, st, st->mid, end, step_save);
        run_chunks(pb, st, st->mid, end, step_rotate);
    }
    return st->mid;
}

static size_t top_add(par_build *pb) {
    if (!array_reserve((void **)&pb->top, &pb->top_cap, pb->top_count + 1, sizeof *pb->top)) {
        pb->failed = true;
        return NO_SUBTREE;
    }
    memset(&pb->top[pb->top_count], 0, sizeof *pb->top);
    pb->top[pb->top_count].subtree = NO_SUBTREE;
    return pb->top_count++;
}

// Splits prims[begin, end) as build_range does, on every thread, down to the subtrees; returns its top_node.
static size_t top_range(par_build *pb, size_t begin, size_t end, uint64_t depth) {
    size_t id = pb->failed ? NO_SUBTREE : top_add(pb);
    if (id == NO_SUBTREE) return id;
    size_t n = end - begin;
    if (n < pb->subtree_min) {
        if (!array_reserve((void **)&pb->subtrees, &pb->subtree_cap, pb->subtree_count + 1, sizeof *pb->subtrees)) {
            pb->failed = true;
            return id;
        }
        pb->subtrees[pb->subtree_count] = (subtree){.begin = begin, .end = end, .depth = depth};
        pb->top[id].subtree = pb->subtree_count++;
        return id;
    }
    builder *bd = &pb->proto;
    if (depth + 1 > bd->depth) bd->depth = depth + 1;
    range_step st = {.pb = pb};
    run_chunks(pb, &st, begin, end, step_bounds);
    box3 bounds = box_empty(), cbounds = box_empty();
    for (size_t k = 0; k < st.count; k++) {
        box_grow(&bounds, &pb->chunks[k].bounds);
        box_grow(&cbounds, &pb->chunks[k].cbounds);
    }
    box_canonical(&bounds);
    box_canonical(&cbounds);
    node_set_box(&pb->top[id].node, &bounds);
    bool stopped = stop_requested(bd);
    split s = {-1, 0, INFINITY};
    bins b;
    if (!stopped && n > 1 && depth + 1 < BVH_MAX_DEPTH) {
        bins_init(&b, n, &cbounds);
        st.b = &b;
        run_chunks(pb, &st, begin, end, step_bins);
        for (size_t k = 0; k < st.count; k++) bins_merge(&b, &pb->chunk_bins[k]);
        s = best_split(bd, &b, &bounds);
    }
    if (stopped || keep_leaf(bd, begin, n, depth, s.cost)) {
        node_set_leaf(bd, &pb->top[id].node, begin, n);
        return id;
    }
    size_t mid = s.axis >= 0 ? parallel_partition(pb, &st, begin, end, &b, s) : begin + n / 2;
    top_range(pb, begin, mid, depth + 1);
    size_t right = top_range(pb, mid, end, depth + 1);
    pb->top[id].right = right;
    return id;
}

static int larger_subtree_first(const void *x, const void *y) {
    const subtree *a = *(const subtree *const *)x, *b = *(const subtree *const *)y;
    size_t na = a->end - a->begin, nb = b->end - b->begin;
    if (na != nb) return na > nb ? -1 : 1;
    return (a->begin > b->begin) - (a->begin < b->begin);
}

static void subtree_build(void *ctx, size_t k) {
    subtree *t = ((subtree **)ctx)[k];
    size_t n = t->end - t->begin;
    t->bd.nodes = malloc((2 * n - 1) * sizeof *t->bd.nodes);
    if (!t->bd.nodes) {
        t->failed = true;
        return;
    }
    build_range(&t->bd, t->begin, t->end, t->depth, NULL);
    // Most of the bound of 2n - 1 nodes is unused: give it back until the copy.
    bvh2_node *fit = realloc(t->bd.nodes, t->bd.node_count * sizeof *fit);
    if (fit) t->bd.nodes = fit;
}

/// The node array the subtrees are copied into.
typedef struct subtree_copy {
    subtree *subtrees;
    bvh2_node *nodes;
} subtree_copy;

static void subtree_place(void *ctx, size_t k) {
    subtree_copy *cp = ctx;
    subtree *t = &cp->subtrees[k];
    bvh2_node *dst = cp->nodes + t->base;
    for (size_t i = 0; i < t->bd.node_count; i++) {
        dst[i] = t->bd.nodes[i];
        if (dst[i].count == 0) dst[i].offset += t->base; // an inner node's second child moves with it
    }
    free(t->bd.nodes);
    t->bd.nodes = NULL;
}

// Builds the tree of build_range(bd, 0, n, 0) into bd->nodes on the pool's threads; the statistics and
// `stopped` as build_range leaves them. False when out of memory.
static bool build_parallel(builder *bd, size_t n, thread_pool *pool, size_t parallel_min) {
    size_t threads = (size_t)thread_pool_size(pool), fair = n / (SUBTREES_PER_THREAD * threads);
    par_build pb = {.proto = *bd, .pool = pool};
    pb.proto.nodes = NULL;
    pb.subtree_min = fair > parallel_min ? fair : parallel_min;
    pb.grain = parallel_min / CHUNK_DIVISOR ? parallel_min / CHUNK_DIVISOR : 1;
    pb.max_chunks = CHUNKS_PER_THREAD * threads;
    pb.chunks = malloc(pb.max_chunks * sizeof *pb.chunks);
    pb.chunk_bins = malloc(pb.max_chunks * sizeof *pb.chunk_bins);
    pb.left = malloc(n);
    pb.front_right = malloc((n / 2 + 1) * sizeof *pb.front_right);
    pb.back_left = malloc((n / 2 + 1) * sizeof *pb.back_left);
    subtree **order = NULL;
    pb.failed = !pb.chunks || !pb.chunk_bins || !pb.left || !pb.front_right || !pb.back_left;
    if (!pb.failed) top_range(&pb, 0, n, 0);
    free(pb.chunks);
    free(pb.chunk_bins);
    free(pb.left);
    free(pb.front_right);
    free(pb.back_left);

    if (!pb.failed && pb.subtree_count) {
        order = malloc(pb.subtree_count * sizeof *order);
        pb.failed = !order;
    }
    if (!pb.failed && !pb.proto.stopped && pb.subtree_count) { // qsort must not see a NULL array
        for (size_t i = 0; i < pb.subtree_count; i++) {
            subtree *t = &pb.subtrees[i];
            t->bd = pb.proto;
            t->bd.node_count = t->bd.leaves = t->bd.depth = 0;
            order[i] = t;
        }
        qsort(order, pb.subtree_count, sizeof *order, larger_subtree_first);
        thread_pool_run(pool, pb.subtree_count, subtree_build, order);
    }
    bool stopped = pb.proto.stopped;
    for (size_t i = 0; i < pb.subtree_count; i++) {
        pb.failed = pb.failed || pb.subtrees[i].failed;
        stopped = stopped || pb.subtrees[i].bd.stopped;
    }
    if (!pb.failed && !stopped) {
        // Number the nodes depth-first: a subtree takes as many places as it has nodes.
        size_t next = 0;
        for (size_t i = 0; i < pb.top_count; i++) {
            top_node *t = &pb.top[i];
            t->index = (uint32_t)next;
            if (t->subtree == NO_SUBTREE) {
                next++;
            } else {
                pb.subtrees[t->subtree].base = t->index;
                next += pb.subtrees[t->subtree].bd.node_count;
            }
        }
        for (size_t i = 0; i < pb.top_count; i++) {
            top_node *t = &pb.top[i];
            if (t->subtree != NO_SUBTREE) continue;
            if (t->node.count == 0) t->node.offset = pb.top[t->right].index;
            bd->nodes[t->index] = t->node;
        }
        subtree_copy cp = {pb.subtrees, bd->nodes};
        thread_pool_run(pool, pb.subtree_count, subtree_place, &cp);
        bd->node_count = next;
        bd->leaves = pb.proto.leaves;
        bd->depth = pb.proto.depth;
        for (size_t i = 0; i < pb.subtree_count; i++) {
            bd->leaves += pb.subtrees[i].bd.leaves;
            if (pb.subtrees[i].bd.depth > bd->depth) bd->depth = pb.subtrees[i].bd.depth;
        }
    }
    bd->stopped = stopped;
    for (size_t i = 0; i < pb.subtree_count; i++) free(pb.subtrees[i].bd.nodes);
    free(pb.subtrees);
    free(pb.top);
    free(order);
    return !pb.failed;
}

/// A binary leaf: its references refs[offset, offset + count).
typedef struct leaf_span {
    uint32_t offset, count;
    uint32_t slot; ///< the first slot of its packets in the arena
} leaf_span;

/// State of the collapse into the wide BVH. It runs in two passes so that the binary nodes are gone before the
/// packet arena fills: the first makes the wide nodes and lists the leaves in the order their packets take in the
/// arena (a leaf's child reference holds its number in the list meanwhile), the second writes the packets.
typedef struct collapser {
    bvh *b;
    uint64_t depth, leaves;
    leaf_span *spans; ///< the leaves, in arena order
    size_t span_count;
    size_t slots;     ///< the arena's size: the slots of the listed leaves' packets
} collapser;

static float node2_half_area(const bvh2_node *n) {
    box3 b = box_empty();
    memcpy(b.lo, n->box, 3 * sizeof(float));
    memcpy(b.hi, n->box + 3, 3 * sizeof(float));
    return box_half_area(&b);
}

static int ref_order(const void *a, const void *b) {
    const prim_ref *x = a, *y = b;
    if (x->kind != y->kind) return x->kind < y->kind ? -1 : 1;
    if (x->instance != y->instance) return x->instance < y->instance ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

// Sorts references by ref_order (a total order: any sort gives the same result): by insertion for the small
// leaves the SAH makes, where qsort's calls through a pointer cost more than the sorting.
static void sort_refs(prim_ref *refs, size_t n) {
    if (n > 16) {
        qsort(refs, n, sizeof *refs, ref_order);
        return;
    }
    for (size_t i = 1; i < n; i++) {
        prim_ref r = refs[i];
        size_t j = i;
        for (; j > 0 && ref_order(&r, &refs[j - 1]) < 0; j--) refs[j] = refs[j - 1];
        refs[j] = r;
    }
}

// Quads are tested as two triangles in triangle packets; other kinds that are not spheres as indices.
static size_t packet_slots(uint32_t kind) {
    size_t bytes = kind == PRIM_SPHERE                            ? sizeof(bvh_sphere_packet)
                   : kind == PRIM_TRIANGLE || kind == PRIM_QUAD ? sizeof(bvh_triangle_packet)
                                                                  : sizeof(bvh_index_packet);
    return bytes / sizeof(bvh_slot);
}

// How many primitives of kind a packet holds (a quad takes two lanes).
static size_t packet_capacity(uint32_t kind) { return kind == PRIM_QUAD ? BVH_PACKET / 2 : BVH_PACKET; }

// How many of the sorted refs[i, count) go into the packet that starts at i: one kind and one instance.
static size_t packet_run(const prim_ref *refs, size_t i, size_t count) {
    size_t n = 0, cap = packet_capacity(refs[i].kind);
    while (i + n < count && n < cap && refs[i + n].kind == refs[i].kind && refs[i + n].instance == refs[i].instance)
        n++;
    return n;
}

// Lists a binary leaf for the second pass and counts the slots of its packets (packet_run); returns its
// temporary reference. The leaf's references are sorted already (sort_leaves).
static uint32_t note_leaf(collapser *cl, const bvh2_node *leaf) {
    const prim_ref *refs = &cl->b->refs[leaf->offset];
    size_t first = cl->slots;
    for (size_t i = 0; i < leaf->count; i += packet_run(refs, i, leaf->count)) cl->slots += packet_slots(refs[i].kind);
    cl->spans[cl->span_count] = (leaf_span){leaf->offset, leaf->count, (uint32_t)first};
    return BVH_LEAF | (uint32_t)cl->span_count++;
}

/// Binary nodes whose leaves one pool item sorts.
enum { SORT_NODES_PER_ITEM = 16384 };

typedef struct sort_job {
    bvh2_node *nodes;
    prim_ref *refs;
    size_t count;
} sort_job;

// Sorts the references of every leaf among nodes [item * SORT_NODES_PER_ITEM, ...) by (kind, instance, index),
// which groups them into packets and orders the lanes (leaves own disjoint ranges of refs), and keeps one of
// each: two pieces of a pre-split triangle may share a leaf.
static void sort_leaves_run(void *ctx, size_t item) {
    const sort_job *job = ctx;
    size_t begin = item * SORT_NODES_PER_ITEM, end = begin + SORT_NODES_PER_ITEM;
    if (end > job->count) end = job->count;
    for (size_t i = begin; i < end; i++) {
        bvh2_node *leaf = &job->nodes[i];
        if (leaf->count == 0) continue;
        prim_ref *refs = &job->refs[leaf->offset];
        sort_refs(refs, leaf->count);
        uint32_t kept = 1;
        for (uint32_t k = 1; k < leaf->count; k++)
            if (ref_order(&refs[k], &refs[kept - 1]) != 0) refs[kept++] = refs[k];
        leaf->count = kept;
    }
}

// sort_leaves_run over the whole binary tree, on the pool's threads when there is one.
static void sort_leaves(thread_pool *pool, bvh2_node *nodes, size_t count, prim_ref *refs) {
    sort_job job = {nodes, refs, count};
    size_t items = (count + SORT_NODES_PER_ITEM - 1) / SORT_NODES_PER_ITEM;
    if (pool) thread_pool_run(pool, items, sort_leaves_run, &job);
    else
        for (size_t i = 0; i < items; i++) sort_leaves_run(&job, i);
}

// Writes the corners of triangle `tri` into lane k of packet pk (NaN corners when tri is NULL: never hit).
static void put_triangle(bvh_triangle_packet *pk, size_t k, const vec3 *tri, uint32_t prim) {
    for (int j = 0; j < 3; j++) {
        vec3 p = tri ? tri[j] : v3s(NAN);
        pk->v[j][0][k] = p.x;
        pk->v[j][1][k] = p.y;
        pk->v[j][2][k] = p.z;
    }
    pk->prim[k] = prim;
}

// Writes the packets of a leaf (its references sorted by sort_leaves) into the arena; returns the leaf reference.
static void emit_leaf(const bvh *b, const leaf_span *leaf) {
    const prim_ref *refs = &b->refs[leaf->offset];
    size_t at = leaf->slot;
    bvh_packet_header *last = NULL;
    for (size_t i = 0; i < leaf->count;) {
        uint32_t kind = refs[i].kind, owner = prim_ref_instance(refs[i]);
        size_t n = packet_run(refs, i, leaf->count);
        bvh_slot *slot = &b->slots[at];
        size_t nslots = packet_slots(kind);
        at += nslots;
        memset(slot, 0, nslots * sizeof *slot);
        bvh_packet_header *h = (bvh_packet_header *)(void *)slot;
        h->kind = kind;
        h->count = (uint32_t)n;
        h->slots = (uint32_t)nslots;
        h->instance = owner;
        last = h;
        if (kind == PRIM_SPHERE) {
            bvh_sphere_packet *pk = (bvh_sphere_packet *)(void *)slot;
            for (size_t k = 0; k < BVH_PACKET; k++) {
                if (k < n) {
                    const sphere *sp = &b->spheres[refs[i + k].index];
                    pk->cx[k] = sp->center.x;
                    pk->cy[k] = sp->center.y;
                    pk->cz[k] = sp->center.z;
                    pk->radius[k] = sp->radius;
                    pk->prim[k] = refs[i + k].index;
                } else {
                    // A NaN centre makes the discriminant NaN, which fails the ordered test: never a hit.
                    pk->cx[k] = pk->cy[k] = pk->cz[k] = NAN;
                    pk->radius[k] = 0.0f;
                    pk->prim[k] = UINT32_MAX;
                }
            }
        } else if (kind == PRIM_TRIANGLE) {
            bvh_triangle_packet *pk = (bvh_triangle_packet *)(void *)slot;
            const mesh *m = owner == HIT_NO_INSTANCE ? b->mesh : b->flat[owner];
            for (size_t k = 0; k < BVH_PACKET; k++) {
                vec3 p[3];
                if (k < n) mesh_triangle_positions(m, refs[i + k].index, &p[0], &p[1], &p[2]);
                put_triangle(pk, k, k < n ? p : NULL, k < n ? refs[i + k].index : UINT32_MAX);
            }
        } else if (kind == PRIM_QUAD) {
            bvh_triangle_packet *pk = (bvh_triangle_packet *)(void *)slot;
            for (size_t k = 0; k < BVH_PACKET / 2; k++) {
                const quad *q = k < n ? &b->quads[refs[i + k].index] : NULL;
                uint32_t prim = q ? refs[i + k].index : UINT32_MAX;
                vec3 t0[3], t1[3]; // quad_intersect's two triangles
                if (q) {
                    t0[0] = t1[0] = q->p[0];
                    t0[1] = q->p[1];
                    t0[2] = t1[1] = q->p[2];
                    t1[2] = q->p[3];
                }
                put_triangle(pk, 2 * k, q ? t0 : NULL, prim);
                put_triangle(pk, 2 * k + 1, q ? t1 : NULL, prim);
            }
        } else {
            bvh_index_packet *pk = (bvh_index_packet *)(void *)slot;
            for (size_t k = 0; k < n; k++) pk->prim[k] = refs[i + k].index;
        }
        i += n;
    }
    if (last) last->last = 1;
}

/// Leaves whose packets one pool item writes: enough to outweigh the hand-over.
enum { EMIT_LEAVES_PER_ITEM = 1024 };

/// The packets of a run of listed leaves, written by one thread of the pool (each leaf has its own slots).
typedef struct emit_job {
    const bvh *b;
    const leaf_span *spans;
    size_t count, per_item;
} emit_job;

static void emit_leaves(void *ctx, size_t item) {
    const emit_job *job = ctx;
    size_t begin = item * job->per_item, end = begin + job->per_item < job->count ? begin + job->per_item : job->count;
    for (size_t i = begin; i < end; i++) emit_leaf(job->b, &job->spans[i]);
}

/// The cheapest cover the SAH finds for a binary subtree by at most i children of a wide node (i = 1 .. BVH_WIDTH):
/// cost[i - 1], and how: split[i - 1] = 0 keeps the subtree whole (a leaf, or an inner node that becomes a wide node
/// of its own; always so for i = 1), k > 0 gives k of the i places to its left subtree and i - k to its right.
/// node_split: how the wide node made from an inner node shares its BVH_WIDTH places between its two subtrees.
typedef struct cover {
    float cost[BVH_WIDTH];
    uint8_t split[BVH_WIDTH];
    uint8_t node_split;
} cover;

// Fills covers[id] and those of the subtree below, bottom-up (Ylitie, Karras and Laine's SAH-optimal conversion to
// a wide BVH, without merging leaves): a leaf costs its area times its packets, a wide node its area plus the best
// sharing of its places. Opening the largest child first instead leaves more nodes, many with two or three
// children, whose SAH cost below the root is 9 % higher on the bunny (docs/benchmarks.md).
static void plan_cover(const bvh *b, cover *covers, uint32_t id) {
    const bvh2_node *n = &b->nodes2[id];
    cover *c = &covers[id];
    float area = node2_half_area(n);
    if (n->count > 0) {
        const prim_ref *refs = &b->refs[n->offset];
        size_t packets = 0;
        for (size_t i = 0; i < n->count; i += packet_run(refs, i, n->count)) packets++;
        for (int i = 0; i < BVH_WIDTH; i++) {
            c->cost[i] = area * SAH_INTERSECT_COST * (float)packets;
            c->split[i] = 0;
        }
        return;
    }
    plan_cover(b, covers, id + 1);
    plan_cover(b, covers, n->offset);
    const cover *l = &covers[id + 1], *r = &covers[n->offset];
    // As a wide node: its places shared between the two subtrees.
    float best = INFINITY;
    int best_k = 1;
    for (int k = 1; k < BVH_WIDTH; k++) {
        float v = l->cost[k - 1] + r->cost[BVH_WIDTH - k - 1];
        if (v < best) {
            best = v;
            best_k = k;
        }
    }
    c->cost[0] = area * SAH_TRAVERSAL_COST + best;
    c->split[0] = 0;
    c->node_split = (uint8_t)best_k;
    // In i places of its parent: whole, or its subtrees in k and i - k of them.
    for (int i = 2; i <= BVH_WIDTH; i++) {
        c->cost[i - 1] = c->cost[0];
        c->split[i - 1] = 0;
        for (int k = 1; k < i; k++) {
            float v = l->cost[k - 1] + r->cost[i - k - 1];
            if (v < c->cost[i - 1]) {
                c->cost[i - 1] = v;
                c->split[i - 1] = (uint8_t)k;
            }
        }
    }
}

// Appends to kids the binary nodes that cover subtree `id` in `places` children of a wide node (plan_cover).
static void cover_children(const bvh *b, const cover *covers, uint32_t id, int places, uint32_t *kids, int *nk) {
    const bvh2_node *n = &b->nodes2[id];
    int k = n->count > 0 ? 0 : covers[id].split[places - 1];
    if (k == 0) {
        kids[(*nk)++] = id;
        return;
    }
    cover_children(b, covers, id + 1, k, kids, nk);
    cover_children(b, covers, n->offset, places - k, kids, nk);
}

// Collapses the binary subtree at `id` into wide nodes as plan_cover chose; returns its reference (node index, or
// leaf number: see collapser).
static uint32_t collapse(collapser *cl, const cover *covers, uint32_t id, uint64_t depth) {
    bvh *b = cl->b;
    const bvh2_node *n2 = &b->nodes2[id];
    if (n2->count > 0) return note_leaf(cl, n2);
    if (depth + 1 > cl->depth) cl->depth = depth + 1;
    uint32_t kids[BVH_WIDTH];
    int nk = 0, left = covers[id].node_split;
    cover_children(b, covers, id + 1, left, kids, &nk);
    cover_children(b, covers, n2->offset, BVH_WIDTH - left, kids, &nk);
    uint32_t wid = (uint32_t)b->wnode_count++;
    bvh_wnode *w = &b->wnodes[wid];
    for (int k = 0; k < BVH_WIDTH; k++) {
        if (k >= nk) {
            for (int a = 0; a < 6; a++) w->box[a][k] = NAN; // no ray enters it (bvh.h)
            w->child[k] = BVH_EMPTY;
            continue;
        }
        const bvh2_node *c = &b->nodes2[kids[k]];
        for (int a = 0; a < 3; a++) {
            w->box[a][k] = c->box[a];
            w->box[3 + a][k] = c->box[3 + a];
        }
        w->child[k] = c->count > 0 ? note_leaf(cl, c) : collapse(cl, covers, kids[k], depth + 1);
    }
    return wid;
}

// The first slot of the leaf that a leaf number refers to (other references unchanged).
static uint32_t leaf_placed(const collapser *cl, uint32_t ref) {
    return ref == BVH_EMPTY || !(ref & BVH_LEAF) ? ref : BVH_LEAF | cl->spans[ref & ~BVH_LEAF].slot;
}

// Pads a box so that it stays conservative after the float rounding of the slab test: by 2^-19 of its largest
// coordinate on every axis, or (`per_axis`) of each axis's own. The slab test of an axis rounds by about 2^-24 of its
// plane's and the origin's coordinates, and an origin far beyond the plane (|o| > 2 |plane|) makes an error under
// 2^-22 of t, which the exit distance's widening covers (SLAB_FAR_SCALE); so per axis suffices for boxes whose
// corners are exact (a triangle's, a quad's), and a floor's box is then no thicker than its height needs: a ray
// spawned off the floor starts outside it rather than testing it again. Boxes computed with rounding, of
// transformed or clipped geometry, take the largest coordinate.
static box3 box_padded_by(bounds3 bb, bool per_axis) {
    const float lo[3] = {bb.lo.x, bb.lo.y, bb.lo.z}, hi[3] = {bb.hi.x, bb.hi.y, bb.hi.z};
    float m[3], all = 0.0f;
    for (int k = 0; k < 3; k++) {
        m[k] = max2(fabsf(lo[k]), fabsf(hi[k]));
        all = max2(all, m[k]);
    }
    box3 b = box_empty();
    for (int k = 0; k < 3; k++) {
        float pad = (per_axis ? m[k] : all) * 0x1p-19f + 0x1p-100f;
        b.lo[k] = lo[k] - pad;
        b.hi[k] = hi[k] + pad;
    }
    return b;
}

static box3 box_padded(bounds3 bb) { return box_padded_by(bb, false); }
static box3 box_padded_axes(bounds3 bb) { return box_padded_by(bb, true); }

// Object-space bounds of what an instance places.
static bounds3 instance_object_bounds(const bvh_input *in, const instance *inst) {
    if (inst->kind == INSTANCE_SPHERE) {
        const sphere *sp = &in->instance_spheres[inst->index];
        float r = fabsf(sp->radius);
        return (bounds3){v3_sub(sp->center, v3s(r)), v3_add(sp->center, v3s(r))};
    }
    return in->blas[inst->index].bounds;
}

// The build input of every primitive: kind, index, padded box, centroid.
/// Triangles whose boxes one pool item gathers.
enum { GATHER_PER_ITEM = 16384 };

/// The boxes of a mesh's triangles, gathered by the pool in runs (each into its own places of prims).
typedef struct gather_job {
    const mesh *m;
    build_prim *prims;
    uint32_t owner; ///< prim_ref.instance of every triangle
    size_t per_item;
    box3 *item_box; ///< item_box[i]: the box of item i's triangles (NULL: not wanted)
} gather_job;

static void gather_triangles_run(void *ctx, size_t item) {
    const gather_job *job = ctx;
    size_t begin = item * job->per_item, count = job->m->triangle_count;
    size_t end = begin + job->per_item < count ? begin + job->per_item : count;
    box3 all = box_empty();
    for (size_t k = begin; k < end; k++) {
        vec3 p[3];
        mesh_triangle_positions(job->m, k, &p[0], &p[1], &p[2]);
        job->prims[k].box = box_padded_axes(bounds3_add(bounds3_add(bounds3_add(bounds3_empty(), p[0]), p[1]), p[2]));
        job->prims[k].split_levels = (uint32_t)tri_split_levels(p[0], p[1], p[2]);
        job->prims[k].ref = (prim_ref){.kind = PRIM_TRIANGLE, .index = (uint32_t)k, .instance = job->owner & PRIM_NO_INSTANCE};
        box_grow(&all, &job->prims[k].box);
    }
    if (job->item_box) job->item_box[item] = all;
}

// Gathers the triangles of m into prims[0, triangle_count), on the pool's threads when there is one, and grows
// *all by their boxes (as one pass in index order would: each item's box, grown in item order).
static void gather_triangles(thread_pool *pool, const mesh *m, uint32_t owner, build_prim *prims, box3 *all) {
    size_t items = (m->triangle_count + GATHER_PER_ITEM - 1) / GATHER_PER_ITEM;
    gather_job job = {m, prims, owner, GATHER_PER_ITEM, malloc(items * sizeof(box3))};
    if (pool) thread_pool_run(pool, items, gather_triangles_run, &job);
    else
        for (size_t i = 0; i < items; i++) gather_triangles_run(&job, i);
    if (job.item_box)
        for (size_t i = 0; i < items; i++) box_grow(all, &job.item_box[i]);
    else // no memory for the items' boxes: a pass of its own
        for (size_t k = 0; k < m->triangle_count; k++) box_grow(all, &prims[k].box);
    free(job.item_box);
}

// Gathers the primitives of in into prims (returning how many), with the box of them all in *all and whether they
// are all triangles and quads (triangle packets) in *triangles_only.
static size_t gather_prims(const bvh_input *in, build_prim *prims, thread_pool *pool, box3 *all, bool *triangles_only) {
    size_t n = 0;
    const uint32_t none = PRIM_NO_INSTANCE;
    *all = box_empty();
    *triangles_only = in->sphere_count == 0 && in->moving_sphere_count == 0;
    for (size_t i = 0; i < in->sphere_count; i++) {
        prims[n].box = sphere_box(&in->spheres[i]);
        prims[n].ref = (prim_ref){.kind = PRIM_SPHERE, .index = (uint32_t)i, .instance = none};
        box_grow(all, &prims[n].box);
        n++;
    }
    for (size_t i = 0; i < in->quad_count; i++) {
        prims[n].box = box_padded_axes(quad_bounds(&in->quads[i]));
        prims[n].ref = (prim_ref){.kind = PRIM_QUAD, .index = (uint32_t)i, .instance = none};
        box_grow(all, &prims[n].box);
        n++;
    }
    if (in->mesh) {
        gather_triangles(pool, in->mesh, none, &prims[n], all);
        n += in->mesh->triangle_count;
    }
    for (size_t i = 0; i < in->instance_count; i++) {
        const instance *inst = &in->instances[i];
        if (in->flat && in->flat[i]) { // its triangles in world space, each a primitive of this BVH
            gather_triangles(pool, in->flat[i], (uint32_t)i & PRIM_NO_INSTANCE, &prims[n], all);
            n += in->flat[i]->triangle_count;
            continue;
        }
        bounds3 ob = instance_object_bounds(in, inst);
        if (bounds3_is_empty(ob)) continue; // an instance of an empty mesh: nothing to hit
        if (inst->motion) { // bounded over the whole shutter, and tested at each ray's time
            prims[n].box = box_padded(motion_bounds(&in->motions[inst->motion - 1], ob, in->time0, in->time1));
            prims[n].ref = (prim_ref){.kind = PRIM_MOVING_INSTANCE, .index = (uint32_t)i, .instance = none};
        } else {
            prims[n].box = box_padded(mat4_apply_bounds(&inst->xf.m, ob));
            prims[n].ref = (prim_ref){.kind = PRIM_INSTANCE, .index = (uint32_t)i, .instance = none};
        }
        box_grow(all, &prims[n].box);
        *triangles_only = false;
        n++;
    }
    for (size_t i = 0; i < in->moving_sphere_count; i++) {
        // A centre moving on a line sweeps the segment between its ends: the two end boxes hold the sweep.
        const moving_sphere *ms = &in->moving_spheres[i];
        sphere a = moving_sphere_at(ms, in->time0), b = moving_sphere_at(ms, in->time1);
        prims[n].box = sphere_box(&a);
        box3 bb = sphere_box(&b);
        box_grow(&prims[n].box, &bb);
        prims[n].ref = (prim_ref){.kind = PRIM_MOVING_SPHERE, .index = (uint32_t)i, .instance = none};
        box_grow(all, &prims[n].box);
        n++;
    }
    return n;
}

/* ------------------------------------------------------------------------------------------------ */
/* Pre-splitting long, slanted triangles (tri_split.h)                                                */

/// Primitives whose triangles one pool item looks at for pre-splitting.
enum { SPLIT_PER_ITEM = 16384 };

typedef struct split_job {
    const bvh_input *in;
    build_prim *prims;
    size_t n;     ///< primitives gathered; the extra pieces go after them
    size_t items;
    size_t (*levels)[TRI_SPLIT_MAX_LEVELS + 1]; ///< levels[item][l]: the item's triangles asking for l levels
    size_t *first; ///< first[item]: where the item's extra pieces start, after n
} split_job;

// The corners of triangle primitive p (of the BVH's mesh or of a flattened instance).
static void prim_triangle(const bvh_input *in, prim_ref r, vec3 p[3]) {
    uint32_t owner = prim_ref_instance(r);
    const mesh *m = owner == HIT_NO_INSTANCE ? in->mesh : in->flat[owner];
    mesh_triangle_positions(m, r.index, &p[0], &p[1], &p[2]);
}

static void split_count_run(void *ctx, size_t item) {
    const split_job *job = ctx;
    size_t begin = item * SPLIT_PER_ITEM, end = begin + SPLIT_PER_ITEM < job->n ? begin + SPLIT_PER_ITEM : job->n;
    for (size_t k = begin; k < end; k++)
        if (job->prims[k].ref.kind == PRIM_TRIANGLE) job->levels[item][job->prims[k].split_levels]++;
}

// The pieces beyond the first of the triangles counted in levels.
static size_t split_extra(const size_t levels[TRI_SPLIT_MAX_LEVELS + 1]) {
    size_t extra = 0;
    for (int l = 1; l <= TRI_SPLIT_MAX_LEVELS; l++) extra += levels[l] * (((size_t)1 << l) - 1);
    return extra;
}

static void split_place_run(void *ctx, size_t item) {
    const split_job *job = ctx;
    if (split_extra(job->levels[item]) == 0) return;
    size_t begin = item * SPLIT_PER_ITEM, end = begin + SPLIT_PER_ITEM < job->n ? begin + SPLIT_PER_ITEM : job->n;
    size_t at = job->n + job->first[item];
    for (size_t k = begin; k < end; k++) {
        if (job->prims[k].ref.kind != PRIM_TRIANGLE || job->prims[k].split_levels == 0) continue;
        int levels = (int)job->prims[k].split_levels;
        vec3 p[3];
        prim_triangle(job->in, job->prims[k].ref, p);
        bounds3 piece[1 << TRI_SPLIT_MAX_LEVELS];
        int count = tri_split_bounds(p[0], p[1], p[2], levels, piece);
        if (count == 0) continue; // cannot happen for a triangle that asks for levels; keep its whole box
        job->prims[k].box = box_padded(piece[0]);
        // Every piece counted has its place; a piece found empty (never for a real triangle) repeats the first.
        for (int j = 1; j < 1 << levels; j++)
            job->prims[at++] = (build_prim){box_padded(piece[j < count ? j : 0]), job->prims[k].ref, 0};
    }
}

// Splits the long, slanted triangles among (*prims)[0, n) into pieces, each a reference to its triangle with the
// box of its part (tri_split.h), the extra pieces appended in order: the same array for any number of threads.
// Returns the new count; n when nothing asks to be split or there is no memory for it (the tree is correct either way).
static size_t presplit(const bvh_input *in, build_prim **prims, size_t n, thread_pool *pool) {
    split_job job = {.in = in, .prims = *prims, .n = n, .items = (n + SPLIT_PER_ITEM - 1) / SPLIT_PER_ITEM};
    job.levels = calloc(job.items, sizeof *job.levels);
    job.first = malloc(job.items * sizeof *job.first);
    size_t extra = 0;
    if (!job.levels || !job.first) goto done;
    if (pool) thread_pool_run(pool, job.items, split_count_run, &job);
    else
        for (size_t i = 0; i < job.items; i++) split_count_run(&job, i);
    for (size_t i = 0; i < job.items; i++) {
        job.first[i] = extra;
        extra += split_extra(job.levels[i]);
    }
    // At most 1 << TRI_SPLIT_MAX_LEVELS references a triangle; nothing to split, or no room: the whole boxes.
    if (extra == 0 || n + extra >= BVH_LEAF / 2) {
        extra = 0;
        goto done;
    }
    build_prim *grown = realloc(*prims, (n + extra) * sizeof *grown);
    if (!grown) {
        extra = 0;
        goto done;
    }
    *prims = job.prims = grown;
    if (pool) thread_pool_run(pool, job.items, split_place_run, &job);
    else
        for (size_t i = 0; i < job.items; i++) split_place_run(&job, i);
done:
    free(job.levels);
    free(job.first);
    return n + extra;
}

// A sphere whose box is at least this fraction of the scene's (by surface area) is not put in the wide tree but
// tested after it, against the tree's nearest hit: nearly every ray enters its box anyway (the book's ground
// of radius 1000, whose box is the scene's), and a test without the traversal's branches costs less than
// the tree step that would reach it (+2% on rtiow-final; tested before the tree, to shorten the ray, it
// measured -2.5%). At most one packet of them.
static const float FRONT_AREA_FRACTION = 0.5f;

// Moves the huge spheres (FRONT_AREA_FRACTION) to the end of prims, keeping the others' order; returns how
// many there are.
// `all` is the box of all of them.
static size_t split_front(build_prim *prims, size_t n, const box3 *all) {
    float limit = FRONT_AREA_FRACTION * box_half_area(all);
    size_t front = 0;
    for (size_t i = 0; i < n && front < BVH_PACKET; i++)
        front += prims[i].ref.kind == PRIM_SPHERE && box_half_area(&prims[i].box) >= limit;
    if (front == 0) return 0;
    build_prim *tmp = malloc(front * sizeof *tmp);
    if (!tmp) return 0; // the tree can hold them as well
    size_t kept = 0, moved = 0;
    for (size_t i = 0; i < n; i++) {
        bool huge = moved < front && prims[i].ref.kind == PRIM_SPHERE && box_half_area(&prims[i].box) >= limit;
        if (huge) tmp[moved++] = prims[i];
        else prims[kept++] = prims[i];
    }
    memcpy(&prims[kept], tmp, front * sizeof *tmp);
    free(tmp);
    return front;
}

// Moves every primitive's reference to the front of the array, in order, and gives the rest back: the
// references take the place of the build input, so that the two are never held at once.
static prim_ref *refs_in_place(build_prim *prims, size_t n) {
    prim_ref *refs = (prim_ref *)(void *)prims;
    for (size_t i = 0; i < n; i++) { // refs[i] lies within prims[0..i], which are read already
        prim_ref r;
        memcpy(&r, &prims[i].ref, sizeof r);
        memcpy(&refs[i], &r, sizeof r);
    }
    prim_ref *fit = realloc(refs, n * sizeof *fit);
    return fit ? fit : refs;
}

// Records the build's step `name`, begun at `began`, on the calling thread's timeline (--trace); one branch when off.
static void build_step_traced(const char *name, int64_t began) {
    trace_lane *lane = trace_current();
    if (lane) trace_add(lane, &(trace_event){name, "render", began, trace_clock(), 0, {{0}}});
}

bool bvh_build(bvh *b, const bvh_input *in, bool wide) {
    memset(b, 0, sizeof *b);
    b->spheres = in->spheres;
    b->sphere_count = in->sphere_count;
    b->quads = in->quads;
    b->mesh = in->mesh;
    b->instances = in->instances;
    b->blas = in->blas;
    b->flat = in->flat;
    b->instance_spheres = in->instance_spheres;
    b->moving_spheres = in->moving_spheres;
    b->motions = in->motions;
    b->spheres_only = in->quad_count == 0 && !in->mesh && in->instance_count == 0 && in->moving_sphere_count == 0;
    b->root = BVH_EMPTY;
    b->front = BVH_EMPTY;
    b->bounds = bounds3_empty();
    size_t cap = in->sphere_count + in->quad_count + (in->mesh ? in->mesh->triangle_count : 0) + in->instance_count +
                 in->moving_sphere_count;
    for (size_t i = 0; in->flat && i < in->instance_count; i++) cap += in->flat[i] ? in->flat[i]->triangle_count : 0;
    if (cap == 0) return true;
    if (cap >= BVH_LEAF / 2 || in->instance_count >= PRIM_NO_INSTANCE) return false; // indices must fit their fields

    build_prim *prims = malloc(cap * sizeof *prims);
    if (!prims) return false;
    // Threads for a big build (the same tree for any number): gathering the boxes, the top of the tree, the
    // packets. One thread, or a pool that could not start: serially.
    int threads = in->threads > 0 ? in->threads : thread_pool_online_cpus();
    size_t parallel_min = in->parallel_min ? in->parallel_min : PARALLEL_MIN;
    thread_pool *pool = threads > 1 && cap >= 2 * parallel_min ? thread_pool_start(threads) : NULL;
    if (pool && thread_pool_size(pool) < 2) {
        thread_pool_stop(pool);
        pool = NULL;
    }
    box3 all;
    int64_t began = trace_current() ? trace_clock() : 0;
    size_t n = gather_prims(in, prims, pool, &all, &b->triangles_only);
    build_step_traced("BVH boxes", began);
    b->prim_count = n;
    if (wide && !in->no_presplit && n > 0) {
        began = trace_current() ? trace_clock() : 0;
        n = presplit(in, &prims, n, pool);
        build_step_traced("BVH pre-split", began);
    }
    if (n == 0) {
        thread_pool_stop(pool);
        free(prims);
        return true;
    }
    b->bounds = (bounds3){v3(all.lo[0], all.lo[1], all.lo[2]), v3(all.hi[0], all.hi[1], all.hi[2])};
    // The wide BVH tests the huge spheres (the last `front` prims) on their own, the tree holds the rest.
    size_t front = wide && in->sphere_count ? split_front(prims, n, &all) : 0, tree = n - front;
    b->nodes2 = tree ? malloc((2 * tree - 1) * sizeof *b->nodes2) : NULL;
    if (tree && !b->nodes2) {
        thread_pool_stop(pool);
        free(prims);
        bvh_release(b);
        return false;
    }
    int shift = wide ? (BVH_PACKET == 8 ? 3 : 2) : 0;
    builder bd = {.prims = prims, .nodes = b->nodes2, .block_shift = shift, .block_mask = ((size_t)1 << shift) - 1,
                  .max_leaf = wide ? BVH_PACKET : BIN_MAX_LEAF, .stop = in->stop};
    bool built = true;
    began = trace_current() ? trace_clock() : 0;
    if (tree) {
        if (pool && tree >= 2 * parallel_min) built = build_parallel(&bd, tree, pool, parallel_min);
        else build_range(&bd, 0, tree, 0, NULL);
    }
    if (!built || bd.stopped) {
        thread_pool_stop(pool);
        free(prims);
        bvh_release(b);
        return false;
    }
    build_step_traced("BVH binary tree", began);
    b->node2_count = bd.node_count;
    b->ref_count = n;
    b->refs = refs_in_place(prims, n);
    b->stats.nodes = bd.node_count - bd.leaves;
    b->stats.leaves = bd.leaves;
    b->stats.depth = bd.depth;
    if (!wide) {
        thread_pool_stop(pool);
        return true;
    }

    // The wide nodes (at most one per binary inner node) and the list of leaves, one per binary leaf and the front.
    size_t inner = bd.node_count - bd.leaves;
    b->wnodes = inner ? aligned_alloc(_Alignof(bvh_wnode), inner * sizeof *b->wnodes) : NULL;
    collapser cl = {.b = b, .spans = malloc((bd.leaves + 1) * sizeof *cl.spans)};
    cover *covers = tree ? malloc(b->node2_count * sizeof *covers) : NULL;
    if ((inner && !b->wnodes) || !cl.spans || (tree && !covers)) {
        thread_pool_stop(pool);
        free(cl.spans);
        free(covers);
        bvh_release(b);
        return false;
    }
    bvh2_node front_leaf = {.offset = (uint32_t)tree, .count = (uint32_t)front};
    began = trace_current() ? trace_clock() : 0;
    sort_leaves(pool, b->nodes2, b->node2_count, b->refs);
    sort_refs(&b->refs[tree], front);
    if (front) b->front = note_leaf(&cl, &front_leaf);
    if (tree) {
        plan_cover(b, covers, 0);
        b->root = collapse(&cl, covers, 0, 0);
    }
    free(covers);
    // The binary tree is only scaffolding for the wide one: gone before the arena fills (the peak of the build).
    free(b->nodes2);
    b->nodes2 = NULL;
    b->node2_count = 0;
    b->slots = cl.slots < BVH_LEAF ? aligned_alloc(_Alignof(bvh_slot), cl.slots * sizeof *b->slots) : NULL;
    if (!b->slots) {
        thread_pool_stop(pool);
        free(cl.spans);
        bvh_release(b);
        return false;
    }
    b->slot_count = cl.slots;
    build_step_traced("BVH wide nodes", began);
    began = trace_current() ? trace_clock() : 0;
    emit_job job = {b, cl.spans, cl.span_count, EMIT_LEAVES_PER_ITEM};
    size_t items = (cl.span_count + EMIT_LEAVES_PER_ITEM - 1) / EMIT_LEAVES_PER_ITEM;
    if (pool) thread_pool_run(pool, items, emit_leaves, &job);
    else
        for (size_t i = 0; i < items; i++) emit_leaves(&job, i);
    thread_pool_stop(pool);
    cl.leaves = cl.span_count;
    for (size_t i = 0; i < b->wnode_count; i++)
        for (int k = 0; k < BVH_WIDTH; k++) b->wnodes[i].child[k] = leaf_placed(&cl, b->wnodes[i].child[k]);
    b->front = leaf_placed(&cl, b->front);
    b->root = leaf_placed(&cl, b->root);
    build_step_traced("BVH leaf packets", began);
    free(cl.spans);
    // The packets hold what the wide traversal reads of the references (the binary one reads them).
    free(b->refs);
    b->refs = NULL;
    b->ref_count = 0;
    b->stats.nodes = b->wnode_count;
    b->stats.leaves = cl.leaves;
    b->stats.depth = tree ? cl.depth + 1 : 1; // the leaf level counts, as in the binary tree
    return true;
}

void bvh_release(bvh *b) {
    free(b->nodes2);
    free(b->refs);
    free(b->wnodes);
    free(b->slots);
    b->nodes2 = NULL;
    b->refs = NULL;
    b->wnodes = NULL;
    b->slots = NULL;
}
