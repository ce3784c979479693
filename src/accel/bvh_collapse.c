// bvh_collapse.c — the binary BVH collapsed into the wide one by the SAH-optimal cover plan (plan_cover), its
// leaves listed for their packets (bvh_packets.c), and the wide build's steps from the binary tree to the packets.
#include "accel/bvh_collapse.h"
#include "accel/bvh_packets.h"
#include "accel/bvh_sah.h"
#include "core/big_alloc.h"

#include <stdlib.h>

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

// Lists a binary leaf for the second pass and counts the slots of its packets (packet_run); returns its
// temporary reference. The leaf's references are sorted already (bvh_sort_leaves).
static uint32_t note_leaf(collapser *cl, const bvh2_node *leaf) {
    const prim_ref *refs = &cl->b->refs[leaf->offset];
    size_t first = cl->slots;
    for (size_t i = 0; i < leaf->count; i += packet_run(refs, i, leaf->count)) cl->slots += packet_slots(refs[i].kind);
    cl->spans[cl->span_count] = (leaf_span){leaf->offset, leaf->count, (uint32_t)first};
    return BVH_LEAF | (uint32_t)cl->span_count++;
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

// The wide build's steps from the binary tree: sort the leaves, plan and make the wide nodes, free the binary
// tree, then write the packets into the arena and point the nodes at them.
bool bvh_collapse_wide(bvh *b, thread_pool *pool, size_t leaves, size_t tree, size_t front) {
    // The wide nodes (at most one per binary inner node) and the list of leaves, one per binary leaf and the front.
    size_t inner = b->node2_count - leaves;
    b->wnodes = inner ? big_alloc(_Alignof(bvh_wnode), inner * sizeof *b->wnodes) : NULL;
    collapser cl = {.b = b, .spans = malloc((leaves + 1) * sizeof *cl.spans)};
    cover *covers = tree ? malloc(b->node2_count * sizeof *covers) : NULL;
    if ((inner && !b->wnodes) || !cl.spans || (tree && !covers)) {
        free(cl.spans);
        free(covers);
        return false;
    }
    bvh2_node front_leaf = {.offset = (uint32_t)tree, .count = (uint32_t)front};
    int64_t began = bvh_step_began();
    bvh_sort_leaves(pool, b->nodes2, b->node2_count, b->refs);
    bvh_sort_refs(&b->refs[tree], front);
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
    b->slots = cl.slots < BVH_LEAF ? big_alloc(_Alignof(bvh_slot), cl.slots * sizeof *b->slots) : NULL;
    if (!b->slots) {
        free(cl.spans);
        return false;
    }
    b->slot_count = cl.slots;
    bvh_step_traced("BVH wide nodes", began);
    began = bvh_step_began();
    bvh_emit_packets(pool, b, cl.spans, cl.span_count);
    cl.leaves = cl.span_count;
    for (size_t i = 0; i < b->wnode_count; i++)
        for (int k = 0; k < BVH_WIDTH; k++) b->wnodes[i].child[k] = leaf_placed(&cl, b->wnodes[i].child[k]);
    b->front = leaf_placed(&cl, b->front);
    b->root = leaf_placed(&cl, b->root);
    bvh_step_traced("BVH leaf packets", began);
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
