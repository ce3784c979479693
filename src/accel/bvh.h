// bvh.h — bounding volume hierarchies (private to src/accel and the tests): a binary BVH built with
// binned SAH, and the wide BVH collapsed from it whose boxes and leaf primitives are tested in SIMD.
#ifndef GLINT_BVH_H
#define GLINT_BVH_H

#include "accel/accel.h"
#include "core/vec.h"
#include "geometry/sphere.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

// The SIMD traversal needs AVX2 and FMA (chosen at compile time); otherwise the scalar path is used.
#if defined(__AVX2__) && defined(__FMA__)
#define BVH_SIMD 1
#else
#define BVH_SIMD 0
#endif

/// Children per node of the wide BVH (one AVX register of boxes per axis and side).
#define BVH_WIDTH 8
/// Primitives per leaf packet (one AVX register per coordinate: testing 8 costs the latency of 1).
#ifndef BVH_PACKET
#define BVH_PACKET 8
#endif
/// Depth limit of the binary build; deeper subtrees become (multi-packet) leaves, which bounds the stacks.
#define BVH_MAX_DEPTH 64

/// Kinds of primitive a BVH can hold; a leaf packet holds primitives of one kind.
typedef enum prim_kind { PRIM_SPHERE = 0 } prim_kind;

/// A primitive of the scene: its kind and its index in the scene's array of that kind.
typedef struct prim_ref {
    uint32_t kind, index;
} prim_ref;

/// Binary BVH node (32 bytes): box[0..2] lower and box[3..5] upper bounds; inner nodes have count 0,
/// their first child follows them and `offset` is the second child; leaves hold refs[offset, offset + count).
typedef struct bvh2_node {
    float box[6];
    uint32_t offset, count;
} bvh2_node;

/// Wide BVH node: the boxes of up to BVH_WIDTH children, structure of arrays, and their references.
/// box[a][i] is the lower bound on axis a of child i, box[3 + a][i] the upper; an empty slot has
/// lower = +inf, upper = -inf so that no ray enters it.
typedef struct bvh_wnode {
    _Alignas(64) float box[6][BVH_WIDTH];
    uint32_t child[BVH_WIDTH]; ///< wide node index, or BVH_LEAF | first slot of the leaf's packets
} bvh_wnode;

#define BVH_LEAF 0x80000000u
#define BVH_EMPTY 0xffffffffu

/// Header of a leaf packet (one slot): `count` primitives of `kind`, `slots` slots long including this
/// header; `last` ends the leaf.
typedef struct bvh_packet_header {
    _Alignas(32) uint32_t kind, count, slots, last;
} bvh_packet_header;

/// A packet of up to BVH_PACKET spheres as structure of arrays; unused lanes have NaN centres.
typedef struct bvh_sphere_packet {
    bvh_packet_header h;
    float cx[BVH_PACKET], cy[BVH_PACKET], cz[BVH_PACKET], radius[BVH_PACKET];
    uint32_t prim[BVH_PACKET];
} bvh_sphere_packet;

/// 32-byte unit of the leaf packet arena: every packet and every lane array in it is aligned for AVX.
typedef struct bvh_slot {
    _Alignas(32) float f[8];
} bvh_slot;

/// Everything the traversals need; built once, then read-only.
typedef struct bvh {
    // primitives of the scene, by kind
    const sphere *spheres;
    size_t sphere_count;
    // binary BVH (ACCEL_BVH2); nodes[0] is the root
    bvh2_node *nodes2;
    size_t node2_count;
    prim_ref *refs; ///< primitive references in leaf order
    size_t ref_count;
    // wide BVH (ACCEL_BVH); `root` is a wide node index or a leaf reference
    bvh_wnode *wnodes;
    size_t wnode_count;
    bvh_slot *slots;
    size_t slot_count;
    uint32_t root;
    accel_stats stats;
} bvh;

/// A sphere hit as the callers see it: kind, no instance, no barycentrics.
static inline void bvh_sphere_hit(hit *h, float t, uint32_t prim) {
    h->t = t;
    h->prim = prim;
    h->kind = HIT_SPHERE;
    h->instance = HIT_NO_INSTANCE;
    h->b1 = h->b2 = 0.0f;
}

/// Builds the binary BVH (wide = false) or the wide one over the spheres; false when out of memory.
bool bvh_build(bvh *b, const sphere *spheres, size_t sphere_count, bool wide);
/// Frees what bvh_build allocated.
void bvh_release(bvh *b);

/// Closest hit in the binary BVH.
bool bvh2_intersect(const bvh *b, const ray *r, hit *h);
/// Any hit in the binary BVH.
bool bvh2_occluded(const bvh *b, const ray *r);
/// Closest hit in the wide BVH, SIMD when compiled in (BVH_SIMD), else scalar.
bool bvh_intersect(const bvh *b, const ray *r, hit *h);
/// Any hit in the wide BVH, SIMD when compiled in, else scalar.
bool bvh_occluded(const bvh *b, const ray *r);
/// Closest hits of two independent rays in the wide BVH, their traversals interleaved step by step.
void bvh_intersect2(const bvh *b, const ray *r0, const ray *r1, hit *h0, hit *h1, bool *f0, bool *f1);
/// Closest hit in the wide BVH by the portable scalar path (always compiled, for tests).
bool bvh_intersect_scalar(const bvh *b, const ray *r, hit *h);
/// Any hit in the wide BVH by the portable scalar path.
bool bvh_occluded_scalar(const bvh *b, const ray *r);

#endif
