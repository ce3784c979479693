// bvh_spatial.c — the binary tree with spatial splits (bvh_spatial.h), on one thread. The references are copied into
// a buffer with room for twice as many; each node of at least SPATIAL_MIN_RANGE references weighs the best binned
// object split (bvh_sah.c) against the best of SPATIAL_BINS - 1 planes across its box on each axis, where a triangle
// counts in every slab it crosses with the box of its part there (its corners in the slab and its edges' crossings
// of the slab's planes). A triangle that a chosen plane cuts goes to both sides with the box of each part (clipped
// in double, tri_split.c), unless putting it whole on one side costs the SAH less ("reference unsplitting"). The left
// child's references stay at the front of the node's part of the buffer, the right child's wait at the end of its
// room until the left subtree is built, then move down after it. A spatial split is tried where the object split's
// boxes overlap and the node has room for a copy of its references, and made where it beats the object split by
// SPATIAL_MARGIN; a subtree whose last SPATIAL_MISSES tries found nothing stops trying.
#include "accel/bvh_spatial.h"
#include "accel/bvh_gather.h"
#include "accel/tri_split.h"
#include "core/array.h"

#include <stdlib.h>
#include <string.h>

/// Planes tried on each axis: the boundaries of this many equal slabs of the node's box.
enum { SPATIAL_BINS = 16 };
/// Ranges of fewer primitives are split between whole ones only: the splits that pay are near the top, and trying
/// every small range would cost more build time than it saves.
enum { SPATIAL_MIN_RANGE = 1024 };

/// Spatial splits are made where they cost the SAH less than this fraction of the best object split's cost.
static const float SPATIAL_MARGIN = 0.95f;
/// A subtree stops trying spatial splits after this many nodes in a row on the way down found none worth making: a
/// scan's tree gains none anywhere, and trying every node of it would triple its build.
enum { SPATIAL_MISSES = 4 };

/// A spatial build: the triangles' corners, the references and their room.
typedef struct spatial_run {
    builder *bd;
    const bvh_input *in;
    build_prim *refs; ///< bd->prims, with room for BVH_SPATIAL_GROWTH times the tree's primitives
    struct deferred *later; ///< right subtrees of whole-primitive splits only, built after the rest
    size_t later_count, later_cap;
    thread_pool *pool; ///< the build's threads (NULL: one)
} spatial_run;

/// A right subtree that tries no spatial split (of at least DEFER_MIN references), built after the spatial
/// part of the tree on the pool's threads into nodes of its own, then appended: the same tree for any number of
/// threads. Its parent's `offset` is set when it is placed.
typedef struct deferred {
    size_t begin, end;
    uint64_t depth;
    uint32_t parent;
    builder bd; ///< its build (own nodes, statistics)
} deferred;

/// The smallest subtree deferred (smaller ones are built in place: the pool's hand-off would cost more).
enum { DEFER_MIN = 256 };

/// A spatial split: slabs 0..bin of `axis` on the left, the plane between them at `pos`.
typedef struct spatial_split {
    int axis; ///< -1: none
    int bin;
    float pos, cost;
    float lo, scale; ///< the axis's binning (bin_of), as the partition classifies
    box3 left, right; ///< the two sides' boxes by the sweep
    size_t nl, nr;    ///< and their references, a cut triangle on both
} spatial_split;

/// The slab bins of one axis: the boxes of what lies in each slab, and the references starting and ending in it.
typedef struct slab_bins {
    box3 box[SPATIAL_BINS];
    size_t enter[SPATIAL_BINS], exit[SPATIAL_BINS];
} slab_bins;

static box3 box_intersect(const box3 *a, const box3 *b) {
    box3 r = box_empty();
    for (int k = 0; k < 3; k++) {
        r.lo[k] = a->lo[k] > b->lo[k] ? a->lo[k] : b->lo[k];
        r.hi[k] = a->hi[k] < b->hi[k] ? a->hi[k] : b->hi[k];
    }
    return r;
}

// The box of the part of triangle reference p inside `clip` (within p's own box), padded for the slab test; false
// when the triangle misses it.
static bool piece_box(const spatial_run *r, const build_prim *p, const box3 *clip, box3 *out) {
    vec3 t[3];
    bvh_prim_triangle(r->in, p->ref, t);
    box3 c = box_intersect(&p->box, clip);
    bounds3 b;
    if (!tri_clip_bounds(t[0], t[1], t[2], c.lo, c.hi, &b)) return false;
    box3 padded = bvh_box_padded(b);
    *out = box_intersect(&padded, &p->box); // a piece's box never outgrows its reference's
    return true;
}

/// The slab planes of one axis of a node's box: slab k from lo + k * width, bin_of(x, lo, scale, SPATIAL_BINS) the
/// slab of coordinate x.
typedef struct slab_axis {
    bool live; ///< the box has extent on the axis
    float lo, scale, width;
} slab_axis;

// Grows the bounds [lo, hi] by point q (scalars: a box built from a point's floats would be stored and loaded back).
static inline void grow_point(float lo[3], float hi[3], const float q[3]) {
    for (int c = 0; c < 3; c++) {
        lo[c] = q[c] < lo[c] ? q[c] : lo[c];
        hi[c] = q[c] > hi[c] ? q[c] : hi[c];
    }
}

// Bins triangle t (reference p, crossing slabs first..last of axis a) into those slabs: the part of a triangle in a
// slab is the polygon of its corners inside the slab and its edges' crossings of the slab's planes, so each slab
// gets the box of those points, cut to p's box (an estimate for a piece, whose part is smaller still).
static void slab_triangle(slab_bins *sb, const slab_axis *ax, int a, const build_prim *p, const float t[3][3],
                          int first, int last) {
    float lo[SPATIAL_BINS][3], hi[SPATIAL_BINS][3];
    for (int k = first; k <= last; k++)
        for (int c = 0; c < 3; c++) lo[k][c] = INFINITY, hi[k][c] = -INFINITY;
    int bin[3];
    for (int v = 0; v < 3; v++) {
        int k = bin_of(t[v][a], ax->lo, ax->scale, SPATIAL_BINS);
        bin[v] = k < first ? first : (k > last ? last : k);
        grow_point(lo[bin[v]], hi[bin[v]], t[v]);
    }
    for (int e = 0; e < 3; e++) {
        int u = e, w = (e + 1) % 3;
        if (bin[u] == bin[w]) continue;
        if (bin[u] > bin[w]) u = w, w = e;
        float d = t[w][a] - t[u][a], inv = d != 0.0f ? 1.0f / d : 0.0f;
        for (int k = bin[u] + 1; k <= bin[w]; k++) { // the edge crosses the plane between slabs k - 1 and k
            float x = ax->lo + (float)k * ax->width, f = (x - t[u][a]) * inv;
            f = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
            float q[3];
            for (int c = 0; c < 3; c++) q[c] = t[u][c] + f * (t[w][c] - t[u][c]);
            q[a] = x;
            grow_point(lo[k - 1], hi[k - 1], q);
            grow_point(lo[k], hi[k], q);
        }
    }
    for (int k = first; k <= last; k++) {
        box3 cut = box_empty();
        bool empty = false;
        for (int c = 0; c < 3; c++) {
            cut.lo[c] = lo[k][c] > p->box.lo[c] ? lo[k][c] : p->box.lo[c];
            cut.hi[c] = hi[k][c] < p->box.hi[c] ? hi[k][c] : p->box.hi[c];
            empty = empty || !(cut.lo[c] <= cut.hi[c]);
        }
        if (!empty) box_grow(&sb->box[k], &cut);
    }
}

// Bins r->refs[begin, end) into the slabs of every live axis at once: a triangle into every slab it crosses, with
// the box of its part there; anything else whole, into the slab of its centroid.
static void bin_slabs(const spatial_run *r, size_t begin, size_t end, const slab_axis ax[3], slab_bins sb[3]) {
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < SPATIAL_BINS; k++) {
            sb[a].box[k] = box_empty();
            sb[a].enter[k] = sb[a].exit[k] = 0;
        }
    for (size_t i = begin; i < end; i++) {
        const build_prim *p = &r->refs[i];
        int first[3], last[3];
        bool crosses = false;
        for (int a = 0; a < 3; a++) {
            if (!ax[a].live) continue;
            if (p->ref.kind != PRIM_TRIANGLE) {
                first[a] = last[a] = bin_of(centroid(p, a), ax[a].lo, ax[a].scale, SPATIAL_BINS);
            } else {
                first[a] = bin_of(p->box.lo[a], ax[a].lo, ax[a].scale, SPATIAL_BINS);
                last[a] = bin_of(p->box.hi[a], ax[a].lo, ax[a].scale, SPATIAL_BINS);
            }
            sb[a].enter[first[a]]++, sb[a].exit[last[a]]++;
            if (first[a] == last[a]) box_grow(&sb[a].box[first[a]], &p->box);
            else crosses = true;
        }
        if (!crosses) continue;
        vec3 c[3];
        bvh_prim_triangle(r->in, p->ref, c);
        const float t[3][3] = {{c[0].x, c[0].y, c[0].z}, {c[1].x, c[1].y, c[1].z}, {c[2].x, c[2].y, c[2].z}};
        for (int a = 0; a < 3; a++)
            if (ax[a].live && first[a] != last[a]) slab_triangle(&sb[a], &ax[a], a, p, t, first[a], last[a]);
    }
}

/// Chunks a large node's slab binning is cut into, for the pool's threads: the bins are the same for any cut (boxes
/// by min and max, counts by sums), so the tree is the same for any number of threads.
enum { SLAB_CHUNKS = 16 };
/// Nodes of at least this many references bin their slabs on the pool.
enum { SLAB_PARALLEL_MIN = 16384 };

/// One node's slab binning cut into chunks (a pool job): each chunk's bins, merged after.
typedef struct slab_job {
    const spatial_run *r;
    size_t begin, end;
    const slab_axis *ax;
    slab_bins (*bins)[3]; ///< SLAB_CHUNKS of them
} slab_job;

static void slab_chunk(void *ctx, size_t k) {
    const slab_job *job = ctx;
    size_t n = job->end - job->begin;
    bin_slabs(job->r, job->begin + n * k / SLAB_CHUNKS, job->begin + n * (k + 1) / SLAB_CHUNKS, job->ax,
              job->bins[k]);
}

// bin_slabs over r->refs[begin, end), on the pool's threads for a large node (the same bins either way).
static void bin_slabs_node(const spatial_run *r, size_t begin, size_t end, const slab_axis ax[3], slab_bins sb[3]) {
    slab_bins (*chunk)[3] = r->pool && end - begin >= SLAB_PARALLEL_MIN ? malloc(SLAB_CHUNKS * sizeof *chunk) : NULL;
    if (!chunk) { // one thread, or no memory for the chunks' bins
        bin_slabs(r, begin, end, ax, sb);
        return;
    }
    slab_job job = {r, begin, end, ax, chunk};
    thread_pool_run(r->pool, SLAB_CHUNKS, slab_chunk, &job);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < SPATIAL_BINS; k++) {
            sb[a].box[k] = box_empty();
            sb[a].enter[k] = sb[a].exit[k] = 0;
            for (int c = 0; c < SLAB_CHUNKS; c++) {
                box_grow(&sb[a].box[k], &chunk[c][a].box[k]);
                sb[a].enter[k] += chunk[c][a].enter[k];
                sb[a].exit[k] += chunk[c][a].exit[k];
            }
        }
    free(chunk);
}

// The best spatial split of r->refs[begin, end) in box `bounds` over the three axes (axis -1: none).
static spatial_split best_spatial(const spatial_run *r, size_t begin, size_t end, const box3 *bounds) {
    const builder *bd = r->bd;
    spatial_split best = {.axis = -1, .cost = INFINITY};
    float area = box_half_area(bounds), inv_area = area > 0.0f ? 1.0f / area : 1.0f;
    slab_axis ax[3];
    for (int a = 0; a < 3; a++) {
        float lo = bounds->lo[a], extent = bounds->hi[a] - lo;
        ax[a].live = extent > 0.0f;
        ax[a].lo = lo;
        ax[a].scale = ax[a].live ? (float)SPATIAL_BINS * (1.0f - 0x1p-20f) / extent : 0.0f;
        ax[a].width = extent / (float)SPATIAL_BINS;
    }
    slab_bins sb[3];
    bin_slabs_node(r, begin, end, ax, sb);
    for (int a = 0; a < 3; a++) {
        if (!ax[a].live) continue;
        box3 right_box[SPATIAL_BINS], acc = box_empty();
        size_t right_count[SPATIAL_BINS], cnt = 0;
        for (int k = SPATIAL_BINS - 1; k > 0; k--) {
            box_grow(&acc, &sb[a].box[k]);
            cnt += sb[a].exit[k];
            right_box[k] = acc;
            right_count[k] = cnt;
        }
        acc = box_empty();
        cnt = 0;
        for (int k = 0; k < SPATIAL_BINS - 1; k++) {
            box_grow(&acc, &sb[a].box[k]);
            cnt += sb[a].enter[k];
            size_t nr = right_count[k + 1];
            if (cnt == 0 || nr == 0) continue;
            float cost = SAH_TRAVERSAL_COST + SAH_INTERSECT_COST * inv_area *
                                                  (box_half_area(&acc) * leaf_blocks(bd, cnt) +
                                                   box_half_area(&right_box[k + 1]) * leaf_blocks(bd, nr));
            if (cost < best.cost)
                best = (spatial_split){a, k, ax[a].lo + (float)(k + 1) * ax[a].width, cost, ax[a].lo, ax[a].scale, acc,
                                       right_box[k + 1], cnt, nr};
        }
    }
    return best;
}

// Whether the object split s (binned in b) leaves its two boxes overlapping, where cut triangles could part them;
// always when it found no split.
static bool overlapping(const bins *b, split s) {
    if (s.axis < 0) return true;
    box3 left = box_empty(), right = box_empty();
    for (int k = 0; k < b->nb; k++) box_grow(k <= s.bin ? &left : &right, &b->box[s.axis][k]);
    box3 both = box_intersect(&left, &right);
    return box_half_area(&both) > 0.0f;
}

// Which side of split ss reference p goes to: 0 left, 1 right, 2 both (cut), unless whole on one side costs the SAH
// less than cutting (reference unsplitting, with the sweep's boxes and counts).
static int spatial_side(const spatial_split *ss, const build_prim *p) {
    int a = ss->axis;
    if (p->ref.kind != PRIM_TRIANGLE) return bin_of(centroid(p, a), ss->lo, ss->scale, SPATIAL_BINS) <= ss->bin ? 0 : 1;
    if (bin_of(p->box.hi[a], ss->lo, ss->scale, SPATIAL_BINS) <= ss->bin) return 0;
    if (bin_of(p->box.lo[a], ss->lo, ss->scale, SPATIAL_BINS) > ss->bin) return 1;
    float al = box_half_area(&ss->left), ar = box_half_area(&ss->right);
    float nl = (float)ss->nl, nr = (float)ss->nr;
    box3 gl = ss->left, gr = ss->right;
    box_grow(&gl, &p->box);
    box_grow(&gr, &p->box);
    float cut = al * nl + ar * nr, whole_left = box_half_area(&gl) * nl + ar * (nr - 1.0f),
          whole_right = al * (nl - 1.0f) + box_half_area(&gr) * nr;
    if (whole_left < cut && whole_left <= whole_right) return 0;
    if (whole_right < cut) return 1;
    return 2;
}

// Partitions r->refs[begin, end) by spatial split ss: the left side to [begin, *left_end), the right to
// [*right_begin, room_end), a cut triangle's parts to both. The room past `end` holds a copy of the range. False
// when a side would be empty (every cut triangle put whole on the other side): nothing was cut, and
// r->refs[begin, end) holds the range's references again (in another order).
static bool spatial_partition(const spatial_run *r, const spatial_split *ss, size_t begin, size_t end,
                              size_t room_end, size_t *left_end, size_t *right_begin) {
    size_t l = begin, rb = room_end;
    int a = ss->axis;
    for (size_t i = begin; i < end; i++) {
        build_prim p = r->refs[i]; // read before anything is written over it: l <= i, and rb >= end
        int side = spatial_side(ss, &p);
        if (side == 2) {
            box3 lhalf = p.box, rhalf = p.box, lbox, rbox;
            lhalf.hi[a] = ss->pos;
            rhalf.lo[a] = ss->pos;
            bool has_l = piece_box(r, &p, &lhalf, &lbox), has_r = piece_box(r, &p, &rhalf, &rbox);
            if (has_l && has_r) {
                r->refs[l] = p;
                r->refs[l++].box = lbox;
                r->refs[--rb] = p;
                r->refs[rb].box = rbox;
                continue;
            }
            side = has_l ? 0 : 1;
        }
        if (side == 0) r->refs[l++] = p;
        else r->refs[--rb] = p;
    }
    if (l == begin || rb == room_end) { // one side empty: nothing was cut, every reference is on the other side
        if (l == begin) memmove(&r->refs[begin], &r->refs[rb], (room_end - rb) * sizeof *r->refs);
        return false;
    }
    *left_end = l;
    *right_begin = rb;
    return true;
}

// Partitions r->refs[begin, end) by object split s (binned in b; halves when s found none) in place, then moves the
// right side to the end of the room: the left side is [begin, *left_end), the right [*right_begin, room_end).
static void object_partition(const spatial_run *r, const bins *b, split s, size_t begin, size_t end, size_t room_end,
                             size_t *left_end, size_t *right_begin) {
    size_t mid = begin + (end - begin) / 2;
    box3 side[2], cside[2]; // not kept: a child's box is computed from its references, as after a spatial split
    if (s.axis >= 0) mid = bvh_partition(r->refs, begin, end, b, s, side, cside);
    size_t nr = end - mid;
    memmove(&r->refs[room_end - nr], &r->refs[mid], nr * sizeof *r->refs);
    *left_end = mid;
    *right_begin = room_end - nr;
}

// Builds the subtree over r->refs[begin, end), whose room runs to room_end; returns its node index and leaves in
// *used the end of the references its leaves hold (from begin). `misses`: how many nodes on the way down tried
// spatial splits in a row and found none worth making; at SPATIAL_MISSES the subtree stops trying.
static uint32_t spatial_range(spatial_run *r, size_t begin, size_t end, size_t room_end, uint64_t depth, int misses,
                              size_t *used) {
    builder *bd = r->bd;
    uint32_t id = bvh_new_node(bd);
    if (depth + 1 > bd->depth) bd->depth = depth + 1;
    box3 bounds = box_empty(), cbounds = box_empty();
    bvh_range_bounds(r->refs, begin, end, &bounds, &cbounds);
    box_canonical(&bounds);
    box_canonical(&cbounds);
    node_set_box(&bd->nodes[id], &bounds);
    size_t n = end - begin;
    bool stopped = stop_requested(bd);
    split s = {-1, 0, INFINITY};
    spatial_split ss = {.axis = -1, .cost = INFINITY};
    bins b;
    if (!stopped && n > 1 && depth + 1 < BVH_MAX_DEPTH) {
        bvh_bins_init(&b, n, &cbounds);
        bvh_bins_add(&b, r->refs, begin, end);
        s = bvh_best_split(bd, &b, &bounds);
        if (misses < SPATIAL_MISSES && room_end - end >= n && n >= SPATIAL_MIN_RANGE && overlapping(&b, s)) {
            ss = best_spatial(r, begin, end, &bounds);
            // Only a clear gain pays for the references it adds (a scan's tree gained nothing from marginal ones).
            if (!(ss.cost < SPATIAL_MARGIN * s.cost)) ss.axis = -1, ss.cost = INFINITY;
            misses = ss.axis < 0 ? misses + 1 : 0;
        }
    }
    if (stopped || keep_leaf(bd, r->refs, begin, n, depth, ss.cost < s.cost ? ss.cost : s.cost)) {
        node_set_leaf(bd, &bd->nodes[id], begin, n);
        *used = end;
        return id;
    }
    size_t left_end, right_begin;
    if (!(ss.axis >= 0 && spatial_partition(r, &ss, begin, end, room_end, &left_end, &right_begin)))
        object_partition(r, &b, s, begin, end, room_end, &left_end, &right_begin);
    size_t left_used, nr = room_end - right_begin;
    spatial_range(r, begin, left_end, right_begin, depth + 1, misses, &left_used);
    memmove(&r->refs[left_used], &r->refs[right_begin], nr * sizeof *r->refs);
    bd->nodes[id].count = 0;
    // A right subtree where no spatial split will be tried keeps its references where they are: built later.
    if (nr >= DEFER_MIN && (misses >= SPATIAL_MISSES || nr < SPATIAL_MIN_RANGE)) {
        if (!array_reserve((void **)&r->later, &r->later_cap, r->later_count + 1, sizeof *r->later)) {
            bd->failed = true;
            *used = left_used + nr;
            return id;
        }
        r->later[r->later_count++] = (deferred){.begin = left_used, .end = left_used + nr, .depth = depth + 1,
                                                .parent = id};
        *used = left_used + nr;
        return id;
    }
    bd->nodes[id].offset = spatial_range(r, left_used, left_used + nr, room_end, depth + 1, misses, used);
    return id;
}

// Builds deferred subtree k into its own nodes (a pool item).
static void deferred_build(void *ctx, size_t k) {
    deferred *d = &((spatial_run *)ctx)->later[k];
    size_t n = d->end - d->begin;
    d->bd.nodes = malloc((2 * n - 1) * sizeof *d->bd.nodes);
    if (!d->bd.nodes) {
        d->bd.failed = true;
        return;
    }
    bvh_build_range(&d->bd, d->begin, d->end, d->depth, NULL);
}

// Builds the deferred subtrees (on the pool when there is one) and appends them to bd's nodes in the order they were
// deferred, each parent pointed at its subtree's root.
static void build_deferred(spatial_run *r) {
    thread_pool *pool = r->pool;
    builder *bd = r->bd;
    for (size_t k = 0; k < r->later_count; k++) {
        deferred *d = &r->later[k];
        d->bd = (builder){.prims = r->refs, .block_shift = bd->block_shift, .block_mask = bd->block_mask,
                          .max_leaf = bd->max_leaf, .stop = bd->stop};
    }
    if (pool) thread_pool_run(pool, r->later_count, deferred_build, r);
    else
        for (size_t k = 0; k < r->later_count; k++) deferred_build(r, k);
    for (size_t k = 0; k < r->later_count; k++) {
        deferred *d = &r->later[k];
        bd->failed = bd->failed || d->bd.failed;
        bd->stopped = bd->stopped || d->bd.stopped;
        if (d->bd.failed) continue;
        uint32_t base = (uint32_t)bd->node_count;
        for (size_t i = 0; i < d->bd.node_count; i++) {
            bvh2_node node = d->bd.nodes[i];
            if (node.count == 0) node.offset += base; // an inner node's second child moves with it
            bd->nodes[base + i] = node;
        }
        bd->nodes[d->parent].offset = base;
        bd->node_count += d->bd.node_count;
        bd->leaves += d->bd.leaves;
        if (d->bd.depth > bd->depth) bd->depth = d->bd.depth;
    }
    for (size_t k = 0; k < r->later_count; k++) free(r->later[k].bd.nodes);
    free(r->later);
}

bool bvh_build_spatial(builder *bd, size_t n, size_t front, thread_pool *pool, size_t *used) {
    size_t room = (size_t)BVH_SPATIAL_GROWTH * n;
    build_prim kept[BVH_PACKET]; // the front (at most a packet of huge spheres) waits here while the room is used
    if (front > BVH_PACKET || room / BVH_SPATIAL_GROWTH != n) {
        bd->failed = true;
        return false;
    }
    memcpy(kept, bd->prims + n, front * sizeof *kept);
    build_prim *grown = realloc(bd->prims, (room + front) * sizeof *grown);
    if (!grown) {
        bd->failed = true;
        return false;
    }
    bd->prims = grown;
    spatial_run r = {bd, bd->spatial->in, grown, NULL, 0, 0, pool};
    spatial_range(&r, 0, n, room, 0, 0, used);
    build_deferred(&r);
    memcpy(grown + *used, kept, front * sizeof *kept);
    if (*used + front >= BVH_LEAF / 2) bd->failed = true; // leaf slots and references must fit their fields
    return !bd->failed;
}
