// bvh_packets.h — the wide BVH's leaf packets (private to the build; bvh_packets.c): how references group into
// packets of one kind and one instance, how many slots each takes, and the sorting and writing of the packets.
#ifndef GLINT_BVH_PACKETS_H
#define GLINT_BVH_PACKETS_H

#include "accel/bvh.h"
#include "core/thread_pool.h"

/// A binary leaf listed for the wide BVH: its references refs[offset, offset + count).
typedef struct leaf_span {
    uint32_t offset, count;
    uint32_t slot; ///< the first slot of its packets in the arena
} leaf_span;

/// Slots of a packet of kind: quads are tested as two triangles in triangle packets; other kinds that are not
/// spheres as indices.
static inline size_t packet_slots(uint32_t kind) {
    size_t bytes = kind == PRIM_SPHERE                            ? sizeof(bvh_sphere_packet)
                   : kind == PRIM_TRIANGLE || kind == PRIM_QUAD ? sizeof(bvh_triangle_packet)
                                                                  : sizeof(bvh_index_packet);
    return bytes / sizeof(bvh_slot);
}

/// How many primitives of kind a packet holds (a quad takes two lanes).
static inline size_t packet_capacity(uint32_t kind) { return kind == PRIM_QUAD ? BVH_PACKET / 2 : BVH_PACKET; }

/// How many of the sorted refs[i, count) go into the packet that starts at i: one kind and one instance.
static inline size_t packet_run(const prim_ref *refs, size_t i, size_t count) {
    size_t n = 0, cap = packet_capacity(refs[i].kind);
    while (i + n < count && n < cap && refs[i + n].kind == refs[i].kind && refs[i + n].instance == refs[i].instance)
        n++;
    return n;
}

/// Sorts references by (kind, instance, index).
void bvh_sort_refs(prim_ref *refs, size_t n);
/// Sorts every binary leaf's references (groups them into packets) and drops repeats, on the pool when there is one.
void bvh_sort_leaves(thread_pool *pool, bvh2_node *nodes, size_t count, prim_ref *refs);
/// Writes the packets of the listed leaves into b's slot arena, on the pool when there is one.
void bvh_emit_packets(thread_pool *pool, const bvh *b, const leaf_span *spans, size_t count);

#endif
