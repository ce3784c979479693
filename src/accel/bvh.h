// bvh.h — bounding volume hierarchies (private to src/accel and the tests): a binary BVH built with
// binned SAH, and the wide BVH collapsed from it whose boxes and leaf primitives are tested in SIMD.
//
// Built by bvh_build (bvh_build.c and the files it names). Queried three ways, with the same hits:
// - one ray at a time: bvh_intersect, bvh_occluded (bvh_traverse.c; binary: bvh2_intersect, bvh2_occluded in
//   bvh2_traverse.c);
// - a stream of up to BVH_STREAM (64) rays of any kind, one traversal step of each in turn, so that while one
//   waits for memory the others work: bvh_intersect_stream (bvh_stream.c), where bvh_streams says it pays;
// - a packet of up to BVH_COHERENT (16) coherent rays (a pixel's camera rays), one interval box test of a node
//   for them all: bvh_intersect_coherent (bvh_packet.c), where bvh_coherent says it applies.
#ifndef GLINT_BVH_H
#define GLINT_BVH_H

#include "accel/accel.h"
#include "core/vec.h"
#include "geometry/mesh.h"
#include "geometry/sphere.h"
#include "geometry/transform.h"
#include "geometry/quad.h"
#include "geometry/triangle.h"

#include <stdatomic.h>
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

/// Kinds of primitive a BVH can hold; a leaf packet holds primitives of one kind. The world BVH holds
/// spheres, quads, instances, moving spheres and moving instances (the last two in index packets, tested one by
/// one at the ray's time, so that the other kinds' tests are unchanged), and the triangles of every mesh placed
/// once (flattened: in world space, no instance to enter); the BVH of a mesh placed several times (shared by
/// its instances) holds its triangles.
typedef enum prim_kind {
    PRIM_SPHERE = 0,
    PRIM_QUAD = 1,
    PRIM_TRIANGLE = 2,
    PRIM_INSTANCE = 3,
    PRIM_MOVING_SPHERE = 4,
    PRIM_MOVING_INSTANCE = 5
} prim_kind;

/// A primitive of the scene: its kind and its index in the scene's array of that kind; a flattened triangle
/// (see bvh_input.flat) also names its instance, which is PRIM_NO_INSTANCE for everything else. Eight bytes:
/// the build keeps one per primitive.
typedef struct prim_ref {
    uint32_t kind : 4;
    uint32_t instance : 28;
    uint32_t index;
} prim_ref;

/// prim_ref.instance of a primitive that is not a flattened triangle; instances are numbered below it.
#define PRIM_NO_INSTANCE 0x0fffffffu

/// The instance of a reference as hits name it (HIT_NO_INSTANCE for none).
static inline uint32_t prim_ref_instance(prim_ref r) {
    return r.instance == PRIM_NO_INSTANCE ? HIT_NO_INSTANCE : (uint32_t)r.instance;
}

/// Binary BVH node (32 bytes): box[0..2] lower and box[3..5] upper bounds; inner nodes have count 0,
/// their first child follows them and `offset` is the second child; leaves hold refs[offset, offset + count).
typedef struct bvh2_node {
    float box[6];
    uint32_t offset, count;
} bvh2_node;

/// Wide BVH node: the boxes of up to BVH_WIDTH children, structure of arrays, and their references.
/// box[a][i] is the lower bound on axis a of child i, box[3 + a][i] the upper; an empty slot's bounds are
/// NaN, which the box tests carry through to their entry distance, so that no ray enters it (a positive NaN: the SIMD
/// test compares distances' bits as integers, where it lies above every number).
typedef struct bvh_wnode {
    _Alignas(64) float box[6][BVH_WIDTH];
    uint32_t child[BVH_WIDTH]; ///< wide node index, or BVH_LEAF | first slot of the leaf's packets
} bvh_wnode;

#define BVH_LEAF 0x80000000u
#define BVH_EMPTY 0xffffffffu

/// Header of a leaf packet (one slot): `count` primitives of `kind`, `slots` slots long including this
/// header; `last` ends the leaf. `instance`: the instance whose flattened triangles the packet holds, else
/// HIT_NO_INSTANCE (a packet holds one instance's triangles).
typedef struct bvh_packet_header {
    _Alignas(32) uint32_t kind; // alone: an alignment specifier applies to every declarator of its declaration
    uint32_t count, slots, last, instance;
} bvh_packet_header;

/// A packet of up to BVH_PACKET spheres as structure of arrays; unused lanes have NaN centres.
typedef struct bvh_sphere_packet {
    bvh_packet_header h;
    float cx[BVH_PACKET], cy[BVH_PACKET], cz[BVH_PACKET], radius[BVH_PACKET];
    uint32_t prim[BVH_PACKET];
} bvh_sphere_packet;

/// A packet of up to BVH_PACKET triangles of the BVH's mesh or of one flattened instance, their vertices
/// gathered as structure of arrays (v[vertex][axis][lane]), so that a packet is tested in SIMD without reading
/// the mesh; unused lanes have NaN vertices, which no ray hits. A packet of kind PRIM_QUAD has this layout too:
/// quad prim[k] is lanes k and k + 1 for even k, its triangles (p0, p1, p2) and (p0, p2, p3).
typedef struct bvh_triangle_packet {
    bvh_packet_header h;
    float v[3][3][BVH_PACKET];
    uint32_t prim[BVH_PACKET];
} bvh_triangle_packet;

/// A packet of up to BVH_PACKET primitives of another kind (quads, instances, moving primitives), tested one by
/// one: their indices.
typedef struct bvh_index_packet {
    bvh_packet_header h;
    uint32_t prim[BVH_PACKET];
} bvh_index_packet;

/// 32-byte unit of the leaf packet arena: every packet and every lane array in it is aligned for AVX.
typedef struct bvh_slot {
    _Alignas(32) float f[8];
} bvh_slot;

/// What a BVH is built over: the world (the one geometry value, with the BVH of every mesh its instances place
/// and the instances accel_build flattened), or the triangles of one mesh. Only the view: the arrays are the
/// geometry value's, pointed at, never copied.
typedef struct bvh_input {
    const geometry_arrays *geometry; ///< world-level spheres, quads, instances, moving spheres (NULL: none)
    const mesh *mesh;                ///< the triangles of one mesh (a mesh's own BVH), or NULL
    const struct bvh *blas;          ///< blas[i]: the BVH of mesh i, for INSTANCE_MESH instances
    const mesh *const *flat;         ///< flat[i]: instance i's mesh in world space, whose triangles the BVH holds
                                     ///< instead of the instance (NULL: not flattened; the array may be NULL)
} bvh_input;

/// Everything the traversals need; built once, then read-only.
typedef struct bvh {
    bvh_input input;     ///< what it is built over; input.geometry is never NULL (an empty value when none was given)
    size_t prim_count;   ///< primitives before pre-splitting
    bool spheres_only;   ///< nothing but spheres: the traversal without the code for other kinds runs
    bool triangles_only; ///< nothing but triangles and quads (triangle packets): likewise
    bool triangles_first; ///< a mixed tree of triangles and quads with few spheres: every ray's triangle-test
                          ///< constants are made up front, not at its first triangle packet (bvh_build.c)
    // binary BVH (ACCEL_BVH2); nodes[0] is the root. A wide build frees both once its packets are written.
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
    uint32_t front; ///< leaf of the huge spheres, tested after the tree by every query (BVH_EMPTY: none)
    bounds3 bounds; ///< of everything in the BVH (empty when it holds nothing)
    accel_stats stats;
} bvh;

/// Whether candidate hit a wins over b: nearer, or as near and first in (kind, instance, prim) order, so
/// that every structure (and brute force) returns the same primitive when several are hit at the same t.
static inline bool bvh_better(const hit *a, const hit *b) {
    if (a->t != b->t) return a->t < b->t;
    if (a->kind != b->kind) return a->kind < b->kind;
    if (a->instance != b->instance) return a->instance < b->instance;
    return a->prim < b->prim;
}

/// The "no hit yet" record for a ray: t = tmax and a key that every real hit at tmax beats.
static inline hit bvh_no_hit(const ray *r) {
    hit h = {r->tmax, UINT32_MAX, UINT32_MAX, UINT32_MAX, 0.0f, 0.0f};
    return h;
}

/// Builds the binary BVH (wide = false) or the wide one over in (whose arrays must outlive b), as opt says (NULL:
/// the defaults), on opt->threads threads when it is big; false when out of memory or stopped by opt->stop (b is
/// then empty).
bool bvh_build(bvh *b, const bvh_input *in, const accel_build_options *opt, bool wide);
/// Frees what bvh_build allocated.
void bvh_release(bvh *b);

// ---- One ray at a time (bvh_traverse.c: wide; bvh2_traverse.c: binary) ----

/// Closest hit in the binary BVH.
bool bvh2_intersect(const bvh *b, const ray *r, hit *h);
/// Any hit in the binary BVH.
bool bvh2_occluded(const bvh *b, const ray *r);
/// Closest hit in the wide BVH, SIMD when compiled in (BVH_SIMD), else scalar.
bool bvh_intersect(const bvh *b, const ray *r, hit *h);
/// Any hit in the wide BVH, SIMD when compiled in, else scalar. With `occluder` not NULL, the leaf it names (a leaf
/// reference, or BVH_EMPTY) is tested first, and the leaf that answered (BVH_EMPTY: none) is left in it: the same
/// answer, sooner where one leaf blocks a path's shadow rays one after another.
bool bvh_occluded(const bvh *b, const ray *r, uint32_t *occluder);

// ---- Streams (bvh_stream.c): rays traced together, one step of each in turn ----

/// Rays a stream query traces together.
#define BVH_STREAM ACCEL_STREAM
/// Closest hits of n <= BVH_STREAM rays in the wide BVH, traced together (the same hits as bvh_intersect):
/// found[i] says whether rays[i] hit, and hits[i] is then its hit.
void bvh_intersect_stream(const bvh *b, int n, const ray *rays, hit *hits, bool *found);
/// Whether bvh_intersect_stream traces b's rays together (SIMD compiled in, not only spheres, no huge spheres),
/// rather than one by one.
bool bvh_streams(const bvh *b);

// ---- Packets (bvh_packet.c): coherent rays traversed as one, interval box tests ----

/// Most rays bvh_intersect_coherent takes at once.
enum { BVH_COHERENT = 16 };
/// Closest hits of n <= BVH_COHERENT rays that start close together and point alike (a pixel's camera rays),
/// traversed as one packet: the same hits as bvh_intersect on each.
void bvh_intersect_coherent(const bvh *b, int n, const ray *rays, hit *hits, bool *found);
/// Whether bvh_intersect_coherent traverses b's rays as a packet (a tree of triangles, SIMD compiled in).
bool bvh_coherent(const bvh *b);

// ---- The portable scalar path of the single-ray traversal (bvh_traverse.c) ----

/// Closest hit in the wide BVH by the portable scalar path (always compiled, for tests).
bool bvh_intersect_scalar(const bvh *b, const ray *r, hit *h);
/// Any hit in the wide BVH by the portable scalar path.
bool bvh_occluded_scalar(const bvh *b, const ray *r);

#endif
