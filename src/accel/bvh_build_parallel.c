// bvh_build_parallel.c — the binary BVH built on every thread of a pool: exactly the tree of the serial
// bvh_build_range, for any number of threads (the top split range by range by all threads, then subtrees).
#include "accel/bvh_build_parallel.h"
#include "core/array.h"

#include <stdlib.h>

// The parallel build makes exactly the tree of bvh_build_range(bd, 0, n, 0, NULL), for any number of threads.
// Ranges of at least subtree_min primitives (the top of the tree, where the root alone reads every primitive) are
// split one at a time by all threads together: their bounds and bins are computed in chunks and grown together in
// chunk order (the bits of one pass: bvh_range_bounds), and parallel_partition reproduces the serial partition's
// order. Smaller ranges are subtrees, each built by bvh_build_range on one thread into its own node buffer, largest
// first; then every subtree is copied to where the serial build numbers it, its child offsets moved along.

// Defaults (beside PARALLEL_MIN, bvh_build_parallel.h): the top leaves at least SUBTREES_PER_THREAD subtrees per
// thread, for the balance of the threads; a step over a range is cut into at most CHUNKS_PER_THREAD chunks per
// thread, of at least PARALLEL_MIN / CHUNK_DIVISOR primitives.
enum { SUBTREES_PER_THREAD = 4, CHUNKS_PER_THREAD = 4, CHUNK_DIVISOR = 8 };
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
    bvh_range_bounds(st->pb->proto.prims, chunk_begin(st, k), chunk_begin(st, k + 1), &c->bounds, &c->cbounds);
}

// Adds the bins of the primitives that follow into's (the same setup) to into.
static void bins_merge(bins *into, const bins *from) {
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < into->nb; k++) {
            into->count[a][k] += from->count[a][k];
            box_grow(&into->box[a][k], &from->box[a][k]);
        }
}


static void step_bins(void *ctx, size_t k) {
    range_step *st = ctx;
    bins *b = &st->pb->chunk_bins[k];
    *b = *st->b; // empty, with the range's setup
    bvh_bins_add(b, st->pb->proto.prims, chunk_begin(st, k), chunk_begin(st, k + 1));
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

// Splits prims[begin, end) as bvh_build_range does, on every thread, down to the subtrees; returns its top_node.
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
        bvh_bins_init(&b, n, &cbounds);
        st.b = &b;
        run_chunks(pb, &st, begin, end, step_bins);
        for (size_t k = 0; k < st.count; k++) bins_merge(&b, &pb->chunk_bins[k]);
        s = bvh_best_split(bd, &b, &bounds);
    }
    if (stopped || keep_leaf(bd, bd->prims, begin, n, depth, s.cost)) {
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
    bvh_build_range(&t->bd, t->begin, t->end, t->depth, NULL);
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

// Builds the tree of bvh_build_range(bd, 0, n, 0, NULL) into bd->nodes on the pool's threads; the statistics and
// `stopped` as bvh_build_range leaves them. False when out of memory.
bool bvh_build_parallel(builder *bd, size_t n, thread_pool *pool, size_t parallel_min) {
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
