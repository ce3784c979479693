// bvh_sah.h — the bottom of the BVH build (private to the bvh_*.c files of the build): its boxes, its
// per-primitive input, the binned-SAH state and the serial binned-SAH build (bvh_sah.c), which every other step
// of the build uses and which uses none of them. The small box and bin pieces are static inline so that every file
// inlines them.
#ifndef GLINT_BVH_SAH_H
#define GLINT_BVH_SAH_H

#include "accel/bvh.h"

#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#if defined(__SSE4_1__)
#include <smmintrin.h>
#elif defined(__SSE__)
#include <xmmintrin.h>
#endif

/// Most bins per axis of the binned SAH.
enum { SAH_BINS = 32 };

// SAH constants: the cost of visiting a node relative to testing one leaf packet (wide BVH) or one
// primitive (binary BVH). Halving or doubling either changed rtiow-final by less than the noise (1%).
/// Cost of visiting a node.
#define SAH_TRAVERSAL_COST 1.0f
/// Cost of testing one leaf packet (wide) or one primitive (binary).
#define SAH_INTERSECT_COST 1.0f

/// Axis-aligned box; the fourth lanes are zero padding so that a box is two SSE registers.
typedef struct box3 {
    _Alignas(16) float lo[4];
    float hi[4];
} box3;

/// The empty box: every bound infinite the wrong way.
static inline box3 box_empty(void) {
    box3 b = {{INFINITY, INFINITY, INFINITY, 0.0f}, {-INFINITY, -INFINITY, -INFINITY, 0.0f}};
    return b;
}

// min/max as comparisons: fminf/fmaxf are library calls without -ffast-math, and bounds hold no NaN.
/// The larger of a and b (bounds hold no NaN).
static inline float max2(float a, float b) { return a > b ? a : b; }

#if defined(__SSE__)
/// Grows box b by box o.
static inline void box_grow(box3 *b, const box3 *o) {
    _mm_store_ps(b->lo, _mm_min_ps(_mm_load_ps(b->lo), _mm_load_ps(o->lo)));
    _mm_store_ps(b->hi, _mm_max_ps(_mm_load_ps(b->hi), _mm_load_ps(o->hi)));
}

/// Half the surface area of a box (0 when it is empty): dx dy + dy dz + dz dx.
static inline float box_half_area(const box3 *b) {
    // The scalar expression lane by lane: (dx dy, dy dz, dz dx), summed in that order.
    __m128 d = _mm_sub_ps(_mm_load_ps(b->hi), _mm_load_ps(b->lo));
    __m128 ok = _mm_cmpge_ps(d, _mm_setzero_ps());
    if ((_mm_movemask_ps(ok) & 7) != 7) return 0.0f;
    __m128 p = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));
    __m128 sum = _mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, _MM_SHUFFLE(3, 2, 1, 1))),
                            _mm_shuffle_ps(p, p, _MM_SHUFFLE(3, 2, 1, 2)));
    return _mm_cvtss_f32(sum);
}
#else
/// The smaller of a and b (bounds hold no NaN).
static inline float min2(float a, float b) { return a < b ? a : b; }

/// Grows box b by box o.
static inline void box_grow(box3 *b, const box3 *o) {
    for (int a = 0; a < 4; a++) {
        b->lo[a] = min2(b->lo[a], o->lo[a]);
        b->hi[a] = max2(b->hi[a], o->hi[a]);
    }
}

/// Half the surface area of a box (0 when it is empty): dx dy + dy dz + dz dx.
static inline float box_half_area(const box3 *b) {
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    if (!(dx >= 0.0f && dy >= 0.0f && dz >= 0.0f)) return 0.0f;
    return dx * dy + dy * dz + dz * dx;
}
#endif

/// Gives zero bounds one sign (+0): the box of a set of primitives is then the same bits whatever the order they
/// were grown in, so that bounds grown during a partition equal bvh_range_bounds' (and the parallel build's).
static inline void box_canonical(box3 *b) {
    for (int a = 0; a < 4; a++) {
        b->lo[a] += 0.0f;
        b->hi[a] += 0.0f;
    }
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

/// The state of one binary build (the serial one, or one subtree or the top of the parallel one).
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
    bool failed; ///< out of memory on the way: the build gives up
    const struct bvh_spatial *spatial; ///< spatial splits (bvh_build_spatial builds the tree), or NULL
} builder;

/// A spatial build's references are at most this many times its primitives (its room; bvh_spatial.c).
enum { BVH_SPATIAL_GROWTH = 2 };

/// The most nodes a build over n primitives can make: two per leaf, and a leaf per reference.
static inline size_t bvh_node_room(const builder *bd, size_t n) {
    return 2 * n * (bd->spatial ? (size_t)BVH_SPATIAL_GROWTH : 1) - 1;
}

/// A new node of bd's tree (its array has room: bvh_build sizes it for every reference the build may make).
static inline uint32_t bvh_new_node(builder *bd) { return (uint32_t)bd->node_count++; }

/// Bin of a centroid coordinate; the same arithmetic when binning and when partitioning.
static inline int bin_of(float c, float lo, float scale, int bins) {
    int k = (int)((c - lo) * scale);
    return k < 0 ? 0 : (k >= bins ? bins - 1 : k);
}

/// The blocks of primitives a leaf of n costs the SAH.
static inline float leaf_blocks(const builder *bd, size_t n) {
    return (float)((n + bd->block_mask) >> bd->block_shift);
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

/// A split of a range: the primitives in bins 0..bin of the axis go left.
typedef struct split {
    int axis; ///< -1: none (every centroid coincides, or the range was not binned)
    int bin;
    float cost;
} split;

/// Whether prims[begin, begin + n) are of one kind (and, flattened triangles, of one instance): one packet's worth.
static inline bool one_kind(const build_prim *prims, size_t begin, size_t n) {
    for (size_t i = begin + 1; i < begin + n; i++)
        if (prims[i].ref.kind != prims[begin].ref.kind || prims[i].ref.instance != prims[begin].ref.instance)
            return false;
    return true;
}

/// Whether prims[begin, begin + n) at `depth` stay a leaf: one primitive, the depth limit, or a leaf of one kind
/// that the SAH prefers to the best split (unless it holds too many primitives for a leaf).
static inline bool keep_leaf(const builder *bd, const build_prim *prims, size_t begin, size_t n, uint64_t depth,
                             float split_cost) {
    // Kinds go to packets of their own: a floor's quad in a leaf with the triangles beside it would make that
    // leaf's box as wide as the floor and as high as the triangles, and every ray leaving the floor would start
    // in it and test them all.
    if (n <= 1 || depth + 1 >= BVH_MAX_DEPTH) return true;
    return n <= (size_t)bd->max_leaf && leaf_blocks(bd, n) * SAH_INTERSECT_COST <= split_cost &&
           one_kind(prims, begin, n);
}

/// Whether a stop was requested: then every range left becomes a leaf, and bvh_build discards the tree.
static inline bool stop_requested(builder *bd) {
    if (!bd->stopped && bd->stop && atomic_load_explicit(bd->stop, memory_order_relaxed)) bd->stopped = true;
    return bd->stopped;
}

/// Stores box b as a binary node's bounds.
static inline void node_set_box(bvh2_node *node, const box3 *b) {
    memcpy(node->box, b->lo, 3 * sizeof(float));
    memcpy(node->box + 3, b->hi, 3 * sizeof(float));
}

/// Makes a binary node the leaf of prims[begin, begin + n).
static inline void node_set_leaf(builder *bd, bvh2_node *node, size_t begin, size_t n) {
    node->offset = (uint32_t)begin;
    node->count = (uint32_t)n;
    bd->leaves++;
}

// ---- bvh_sah.c: the serial binned SAH and the build's traced steps ----

/// Grows *bounds and *cbounds by the boxes and the centroids of prims[begin, end), in index order (the bits of one
/// pass over the range when consecutive chunks' results are grown in their order).
void bvh_range_bounds(const build_prim *prims, size_t begin, size_t end, box3 *bounds, box3 *cbounds);
/// Empty bins for n primitives over the centroid box cbounds.
void bvh_bins_init(bins *b, size_t n, const box3 *cbounds);
/// Bins prims[begin, end) on all three axes in one pass.
void bvh_bins_add(bins *b, const build_prim *prims, size_t begin, size_t end);
/// Partitions prims[begin, end) by split s (of the bins b; s.axis >= 0), left side first, and returns where the right
/// side starts; side[k] and cside[k] get the boxes and centroid boxes of the two sides.
size_t bvh_partition(build_prim *prims, size_t begin, size_t end, const bins *b, split s, box3 side[2],
                     box3 cside[2]);
/// The best binned SAH split over the three axes of a range with box `bounds`.
split bvh_best_split(const builder *bd, const bins *b, const box3 *bounds);
/// Builds the subtree over prims[begin, end) at `depth` into bd (depth-first) and returns its node index; `known`:
/// its box and centroid box, or NULL.
uint32_t bvh_build_range(builder *bd, size_t begin, size_t end, uint64_t depth, const box3 *known);
/// The clock reading that starts a traced step (0 when no trace records).
int64_t bvh_step_began(void);
/// Records the build's step `name`, begun at `began`, on the calling thread's timeline (--trace).
void bvh_step_traced(const char *name, int64_t began);

#endif
