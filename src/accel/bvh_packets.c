// bvh_packets.c — the wide BVH's leaf packets: every binary leaf's references sorted into packets of one kind and
// one instance, and the packets written into the slot arena (spheres and triangles as structure of arrays).
#include "accel/bvh_packets.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(bvh_packet_header) == sizeof(bvh_slot), "a packet's header is one slot");
_Static_assert(sizeof(bvh_sphere_packet) % sizeof(bvh_slot) == 0, "a packet is a whole number of slots");
_Static_assert(offsetof(bvh_sphere_packet, cx) % (BVH_PACKET * sizeof(float)) == 0, "lanes aligned for SIMD loads");
_Static_assert(sizeof(bvh_triangle_packet) % sizeof(bvh_slot) == 0, "a packet is a whole number of slots");
_Static_assert(offsetof(bvh_triangle_packet, v) % (BVH_PACKET * sizeof(float)) == 0, "lanes aligned for SIMD loads");

static int ref_order(const void *a, const void *b) {
    const prim_ref *x = a, *y = b;
    if (x->kind != y->kind) return x->kind < y->kind ? -1 : 1;
    if (x->instance != y->instance) return x->instance < y->instance ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

// Sorts references by ref_order (a total order: any sort gives the same result): by insertion for the small
// leaves the SAH makes, where qsort's calls through a pointer cost more than the sorting.
void bvh_sort_refs(prim_ref *refs, size_t n) {
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
        bvh_sort_refs(refs, leaf->count);
        uint32_t kept = 1;
        for (uint32_t k = 1; k < leaf->count; k++)
            if (ref_order(&refs[k], &refs[kept - 1]) != 0) refs[kept++] = refs[k];
        leaf->count = kept;
    }
}

// sort_leaves_run over the whole binary tree, on the pool's threads when there is one.
void bvh_sort_leaves(thread_pool *pool, bvh2_node *nodes, size_t count, prim_ref *refs) {
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

// Writes the packets of a leaf (its references sorted by bvh_sort_leaves) into the arena.
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
                    const sphere *sp = &b->input.geometry->spheres[refs[i + k].index];
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
            const mesh *m = owner == HIT_NO_INSTANCE ? b->input.mesh : b->input.flat[owner];
            for (size_t k = 0; k < BVH_PACKET; k++) {
                vec3 p[3];
                if (k < n) mesh_triangle_positions(m, refs[i + k].index, &p[0], &p[1], &p[2]);
                put_triangle(pk, k, k < n ? p : NULL, k < n ? refs[i + k].index : UINT32_MAX);
            }
        } else if (kind == PRIM_QUAD) {
            bvh_triangle_packet *pk = (bvh_triangle_packet *)(void *)slot;
            for (size_t k = 0; k < BVH_PACKET / 2; k++) {
                const quad *q = k < n ? &b->input.geometry->quads[refs[i + k].index] : NULL;
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

// emit_leaves over every listed leaf, on the pool's threads when there is one.
void bvh_emit_packets(thread_pool *pool, const bvh *b, const leaf_span *spans, size_t count) {
    emit_job job = {b, spans, count, EMIT_LEAVES_PER_ITEM};
    size_t items = (count + EMIT_LEAVES_PER_ITEM - 1) / EMIT_LEAVES_PER_ITEM;
    if (pool) thread_pool_run(pool, items, emit_leaves, &job);
    else
        for (size_t i = 0; i < items; i++) emit_leaves(&job, i);
}
