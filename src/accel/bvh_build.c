// bvh_build.c — binned-SAH construction of the binary BVH, and its collapse into the wide BVH with
// structure-of-arrays leaf packets.
#include "accel/bvh.h"

#include <stdatomic.h>

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

enum { SAH_BINS = 32 };

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
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    if (!(dx >= 0.0f && dy >= 0.0f && dz >= 0.0f)) return 0.0f;
    return dx * dy + dy * dz + dz * dx;
}

/// Per-primitive build input: padded bounds and centroid.
typedef struct build_prim {
    box3 box;
    float c[3];
    prim_ref ref;
} build_prim;

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

// Recursively builds the subtree over prims[begin, end) and returns its node index (depth-first order).
static uint32_t build_range(builder *bd, size_t begin, size_t end, uint64_t depth) {
    uint32_t id = new_node(bd);
    if (depth + 1 > bd->depth) bd->depth = depth + 1;
    box3 bounds = box_empty(), cbounds = box_empty();
    for (size_t i = begin; i < end; i++) {
        box_grow(&bounds, &bd->prims[i].box);
        box3 c = {{bd->prims[i].c[0], bd->prims[i].c[1], bd->prims[i].c[2], 0.0f},
                  {bd->prims[i].c[0], bd->prims[i].c[1], bd->prims[i].c[2], 0.0f}};
        box_grow(&cbounds, &c);
    }
    bvh2_node *node = &bd->nodes[id];
    memcpy(node->box, bounds.lo, 3 * sizeof(float));
    memcpy(node->box + 3, bounds.hi, 3 * sizeof(float));
    size_t n = end - begin;
    // A stop request ends the build: every range left becomes a leaf, and bvh_build discards the tree.
    if (!bd->stopped && bd->stop && atomic_load_explicit(bd->stop, memory_order_relaxed)) bd->stopped = true;
    if (bd->stopped) {
        node->offset = (uint32_t)begin;
        node->count = (uint32_t)n;
        bd->leaves++;
        return id;
    }

    // Best binned SAH split over the three axes.
    float leaf_cost = leaf_blocks(bd, n) * SAH_INTERSECT_COST;
    float best_cost = INFINITY;
    int best_axis = -1, best_bin = 0, best_nb = SAH_BINS;
    float parent_area = box_half_area(&bounds), inv_area = parent_area > 0.0f ? 1.0f / parent_area : 1.0f;
    if (n > 1 && depth + 1 < BVH_MAX_DEPTH) {
        // One pass over the primitives bins them on all three axes (axes with no extent are skipped);
        // small ranges use fewer bins, which costs them nothing in quality and saves most of the sweep.
        int nb = n < SAH_BINS ? (n < 4 ? 4 : (int)n) : SAH_BINS;
        float scale[3];
        bool live[3];
        for (int a = 0; a < 3; a++) {
            float extent = cbounds.hi[a] - cbounds.lo[a];
            live[a] = extent > 0.0f;
            scale[a] = live[a] ? (float)nb * (1.0f - 0x1p-20f) / extent : 0.0f;
        }
        box3 bin_box[3][SAH_BINS];
        size_t bin_count[3][SAH_BINS];
        for (int a = 0; a < 3; a++)
            for (int k = 0; k < nb; k++) {
                bin_box[a][k] = box_empty();
                bin_count[a][k] = 0;
            }
        for (size_t i = begin; i < end; i++) {
            const build_prim *p = &bd->prims[i];
            for (int a = 0; a < 3; a++) {
                int k = bin_of(p->c[a], cbounds.lo[a], scale[a], nb);
                bin_count[a][k]++;
                box_grow(&bin_box[a][k], &p->box);
            }
        }
        for (int a = 0; a < 3; a++) {
            if (!live[a]) continue;
            // Sweep from the right for the areas and counts of every right side.
            float right_area[SAH_BINS];
            size_t right_count[SAH_BINS];
            box3 acc = box_empty();
            size_t cnt = 0;
            for (int k = nb - 1; k > 0; k--) {
                box_grow(&acc, &bin_box[a][k]);
                cnt += bin_count[a][k];
                right_area[k] = box_half_area(&acc);
                right_count[k] = cnt;
            }
            acc = box_empty();
            cnt = 0;
            for (int k = 0; k < nb - 1; k++) {
                box_grow(&acc, &bin_box[a][k]);
                cnt += bin_count[a][k];
                if (cnt == 0 || right_count[k + 1] == 0) continue;
                float cost = SAH_TRAVERSAL_COST + SAH_INTERSECT_COST * inv_area *
                                                      (box_half_area(&acc) * leaf_blocks(bd, cnt) +
                                                       right_area[k + 1] * leaf_blocks(bd, right_count[k + 1]));
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = a;
                    best_bin = k;
                    best_nb = nb;
                }
            }
        }
    }

    bool must_split = n > (size_t)bd->max_leaf && depth + 1 < BVH_MAX_DEPTH;
    if (n <= 1 || depth + 1 >= BVH_MAX_DEPTH || (!must_split && leaf_cost <= best_cost)) {
        node->offset = (uint32_t)begin;
        node->count = (uint32_t)n;
        bd->leaves++;
        return id;
    }

    size_t mid;
    if (best_axis >= 0) {
        // Partition by the chosen bin, recomputed with exactly the arithmetic of the binning.
        int a = best_axis;
        float scale = (float)best_nb * (1.0f - 0x1p-20f) / (cbounds.hi[a] - cbounds.lo[a]);
        size_t i = begin, j = end;
        while (i < j) {
            if (bin_of(bd->prims[i].c[a], cbounds.lo[a], scale, best_nb) <= best_bin) {
                i++;
            } else {
                build_prim tmp = bd->prims[i];
                bd->prims[i] = bd->prims[--j];
                bd->prims[j] = tmp;
            }
        }
        mid = i;
    } else {
        // Every centroid coincides: no split separates them, so halve the range.
        mid = begin + n / 2;
    }
    build_range(bd, begin, mid, depth + 1);
    uint32_t right = build_range(bd, mid, end, depth + 1);
    bd->nodes[id].offset = right;
    bd->nodes[id].count = 0;
    return id;
}

/// State of the collapse into the wide BVH (arrays sized beforehand from the binary tree).
typedef struct collapser {
    bvh *b;
    uint64_t depth, leaves;
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

// Slots the packets of a binary leaf take (packet_run). Sorts the leaf's references by (kind, instance,
// index), which groups them into packets and orders the lanes.
static size_t leaf_slots(bvh *b, const bvh2_node *leaf) {
    prim_ref *refs = &b->refs[leaf->offset];
    qsort(refs, leaf->count, sizeof *refs, ref_order);
    size_t slots = 0;
    for (size_t i = 0; i < leaf->count; i += packet_run(refs, i, leaf->count)) slots += packet_slots(refs[i].kind);
    return slots;
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

// Writes the packets of a binary leaf (its references sorted by leaf_slots) into the arena; returns the
// leaf reference.
static uint32_t emit_leaf(collapser *cl, const bvh2_node *leaf) {
    bvh *b = cl->b;
    const prim_ref *refs = &b->refs[leaf->offset];
    uint32_t first = (uint32_t)b->slot_count;
    bvh_packet_header *last = NULL;
    cl->leaves++;
    for (size_t i = 0; i < leaf->count;) {
        uint32_t kind = refs[i].kind, owner = refs[i].instance;
        size_t n = packet_run(refs, i, leaf->count);
        bvh_slot *slot = &b->slots[b->slot_count];
        size_t nslots = packet_slots(kind);
        b->slot_count += nslots;
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
    return BVH_LEAF | first;
}

// Collapses the binary subtree at `id` into wide nodes; returns its reference (node index or leaf).
static uint32_t collapse(collapser *cl, uint32_t id, uint64_t depth) {
    bvh *b = cl->b;
    const bvh2_node *n2 = &b->nodes2[id];
    if (n2->count > 0) return emit_leaf(cl, n2);
    if (depth + 1 > cl->depth) cl->depth = depth + 1;
    // Open the largest inner child until the node has BVH_WIDTH children or only leaves remain.
    uint32_t kids[BVH_WIDTH];
    int nk = 2;
    kids[0] = id + 1;
    kids[1] = n2->offset;
    while (nk < BVH_WIDTH) {
        int best = -1;
        float best_area = -1.0f;
        for (int k = 0; k < nk; k++) {
            const bvh2_node *c = &b->nodes2[kids[k]];
            if (c->count == 0 && node2_half_area(c) > best_area) {
                best_area = node2_half_area(c);
                best = k;
            }
        }
        if (best < 0) break;
        uint32_t open = kids[best];
        kids[best] = open + 1;
        kids[nk++] = b->nodes2[open].offset;
    }
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
        w->child[k] = c->count > 0 ? emit_leaf(cl, c) : collapse(cl, kids[k], depth + 1);
    }
    return wid;
}

// Pads a box so that it stays conservative after the float rounding of the slab test.
static box3 box_padded(bounds3 bb) {
    float m = max2(max2(max2(fabsf(bb.lo.x), fabsf(bb.hi.x)), max2(fabsf(bb.lo.y), fabsf(bb.hi.y))),
                   max2(fabsf(bb.lo.z), fabsf(bb.hi.z)));
    float pad = m * 0x1p-19f + 0x1p-100f;
    box3 b = box_empty();
    b.lo[0] = bb.lo.x - pad;
    b.lo[1] = bb.lo.y - pad;
    b.lo[2] = bb.lo.z - pad;
    b.hi[0] = bb.hi.x + pad;
    b.hi[1] = bb.hi.y + pad;
    b.hi[2] = bb.hi.z + pad;
    return b;
}

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
static size_t gather_prims(const bvh_input *in, build_prim *prims) {
    size_t n = 0;
    const uint32_t none = HIT_NO_INSTANCE;
    for (size_t i = 0; i < in->sphere_count; i++) {
        prims[n].box = sphere_box(&in->spheres[i]);
        prims[n].ref = (prim_ref){PRIM_SPHERE, (uint32_t)i, none};
        n++;
    }
    for (size_t i = 0; i < in->quad_count; i++) {
        prims[n].box = box_padded(quad_bounds(&in->quads[i]));
        prims[n].ref = (prim_ref){PRIM_QUAD, (uint32_t)i, none};
        n++;
    }
    for (size_t i = 0; in->mesh && i < in->mesh->triangle_count; i++) {
        prims[n].box = box_padded(mesh_triangle_bounds(in->mesh, i));
        prims[n].ref = (prim_ref){PRIM_TRIANGLE, (uint32_t)i, none};
        n++;
    }
    for (size_t i = 0; i < in->instance_count; i++) {
        const instance *inst = &in->instances[i];
        if (in->flat && in->flat[i]) { // its triangles in world space, each a primitive of this BVH
            const mesh *m = in->flat[i];
            for (size_t k = 0; k < m->triangle_count; k++) {
                prims[n].box = box_padded(mesh_triangle_bounds(m, k));
                prims[n].ref = (prim_ref){PRIM_TRIANGLE, (uint32_t)k, (uint32_t)i};
                n++;
            }
            continue;
        }
        bounds3 ob = instance_object_bounds(in, inst);
        if (bounds3_is_empty(ob)) continue; // an instance of an empty mesh: nothing to hit
        if (inst->motion) { // bounded over the whole shutter, and tested at each ray's time
            prims[n].box = box_padded(motion_bounds(&in->motions[inst->motion - 1], ob, in->time0, in->time1));
            prims[n].ref = (prim_ref){PRIM_MOVING_INSTANCE, (uint32_t)i, none};
        } else {
            prims[n].box = box_padded(mat4_apply_bounds(&inst->xf.m, ob));
            prims[n].ref = (prim_ref){PRIM_INSTANCE, (uint32_t)i, none};
        }
        n++;
    }
    for (size_t i = 0; i < in->moving_sphere_count; i++) {
        // A centre moving on a line sweeps the segment between its ends: the two end boxes hold the sweep.
        const moving_sphere *ms = &in->moving_spheres[i];
        sphere a = moving_sphere_at(ms, in->time0), b = moving_sphere_at(ms, in->time1);
        prims[n].box = sphere_box(&a);
        box3 bb = sphere_box(&b);
        box_grow(&prims[n].box, &bb);
        prims[n].ref = (prim_ref){PRIM_MOVING_SPHERE, (uint32_t)i, none};
        n++;
    }
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) prims[i].c[a] = 0.5f * prims[i].box.lo[a] + 0.5f * prims[i].box.hi[a];
    return n;
}

// A sphere whose box is at least this fraction of the scene's (by surface area) is not put in the wide tree but
// tested after it, against the tree's nearest hit: nearly every ray enters its box anyway (the book's ground
// of radius 1000, whose box is the scene's), and a test without the traversal's branches costs less than
// the tree step that would reach it (+2% on rtiow-final; tested before the tree, to shorten the ray, it
// measured -2.5%). At most one packet of them.
static const float FRONT_AREA_FRACTION = 0.5f;

// Moves the huge spheres (FRONT_AREA_FRACTION) to the end of prims, keeping the others' order; returns how
// many there are.
static size_t split_front(build_prim *prims, size_t n) {
    box3 all = box_empty();
    for (size_t i = 0; i < n; i++) box_grow(&all, &prims[i].box);
    float limit = FRONT_AREA_FRACTION * box_half_area(&all);
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
    if (cap >= BVH_LEAF / 2) return false;

    build_prim *prims = malloc(cap * sizeof *prims);
    if (!prims) return false;
    size_t n = gather_prims(in, prims);
    b->prim_count = n;
    if (n == 0) {
        free(prims);
        return true;
    }
    box3 all = box_empty();
    b->triangles_only = true;
    for (size_t i = 0; i < n; i++) {
        box_grow(&all, &prims[i].box);
        b->triangles_only = b->triangles_only && (prims[i].ref.kind == PRIM_TRIANGLE || prims[i].ref.kind == PRIM_QUAD);
    }
    b->bounds = (bounds3){v3(all.lo[0], all.lo[1], all.lo[2]), v3(all.hi[0], all.hi[1], all.hi[2])};
    // The wide BVH tests the huge spheres (the last `front` prims) on their own, the tree holds the rest.
    size_t front = wide ? split_front(prims, n) : 0, tree = n - front;
    b->nodes2 = tree ? malloc((2 * tree - 1) * sizeof *b->nodes2) : NULL;
    b->refs = malloc(n * sizeof *b->refs);
    if ((tree && !b->nodes2) || !b->refs) {
        free(prims);
        bvh_release(b);
        return false;
    }
    int shift = wide ? (BVH_PACKET == 8 ? 3 : 2) : 0;
    builder bd = {.prims = prims, .nodes = b->nodes2, .block_shift = shift, .block_mask = ((size_t)1 << shift) - 1,
                  .max_leaf = wide ? BVH_PACKET : BIN_MAX_LEAF, .stop = in->stop};
    if (tree) build_range(&bd, 0, tree, 0);
    if (bd.stopped) {
        free(prims);
        bvh_release(b);
        return false;
    }
    b->node2_count = bd.node_count;
    b->ref_count = n;
    for (size_t i = 0; i < n; i++) b->refs[i] = prims[i].ref;
    free(prims);
    b->stats.nodes = bd.node_count - bd.leaves;
    b->stats.leaves = bd.leaves;
    b->stats.depth = bd.depth;
    if (!wide) return true;

    // Size the wide arrays from the binary tree: at most one wide node per binary inner node.
    bvh2_node front_leaf = {.offset = (uint32_t)tree, .count = (uint32_t)front};
    size_t inner = bd.node_count - bd.leaves, slots = front ? leaf_slots(b, &front_leaf) : 0;
    for (size_t i = 0; i < bd.node_count; i++)
        if (b->nodes2[i].count > 0) slots += leaf_slots(b, &b->nodes2[i]);
    b->wnodes = inner ? aligned_alloc(_Alignof(bvh_wnode), inner * sizeof *b->wnodes) : NULL;
    b->slots = aligned_alloc(_Alignof(bvh_slot), slots * sizeof *b->slots);
    if ((inner && !b->wnodes) || !b->slots || slots >= BVH_LEAF) {
        bvh_release(b);
        return false;
    }
    collapser cl = {.b = b};
    if (front) b->front = emit_leaf(&cl, &front_leaf);
    if (tree) b->root = collapse(&cl, 0, 0);
    b->stats.nodes = b->wnode_count;
    b->stats.leaves = cl.leaves;
    b->stats.depth = tree ? cl.depth + 1 : 1; // the leaf level counts, as in the binary tree
    // The binary tree is only scaffolding for the wide one.
    free(b->nodes2);
    b->nodes2 = NULL;
    b->node2_count = 0;
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
