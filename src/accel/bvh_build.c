// bvh_build.c — the BVH build's entry point (bvh_build) and the order of its steps: the input (bvh_gather.c), the
// binary tree by the serial binned SAH (bvh_sah.c), on every thread (bvh_build_parallel.c) or, for a wide tree with
// triangles, with spatial splits (bvh_spatial.c), then the wide collapse and its leaf packets (bvh_collapse.c).
#include "accel/bvh_build_parallel.h"
#include "accel/bvh_collapse.h"
#include "accel/bvh_gather.h"
#include "accel/bvh_sah.h"
#include "accel/bvh_spatial.h"

#include <stdlib.h>

// Largest leaf of the binary BVH (its leaves are tested one primitive at a time).
enum { BIN_MAX_LEAF = 4 };

// The geometry of a BVH given none (a mesh's own BVH): every array empty.
static const geometry_arrays no_geometry;

// Points b at what in points at (the view, not the arrays), with nothing built yet.
static void bvh_adopt(bvh *b, const bvh_input *in) {
    memset(b, 0, sizeof *b);
    b->input = *in;
    if (!b->input.geometry) b->input.geometry = &no_geometry;
    const geometry_arrays *g = b->input.geometry;
    b->spheres_only = g->quad_count == 0 && !in->mesh && g->instance_count == 0 && g->moving_sphere_count == 0;
    b->root = BVH_EMPTY;
    b->front = BVH_EMPTY;
    b->bounds = bounds3_empty();
}

// The primitives in's arrays hold before pre-splitting: the length of the build's input array.
static size_t input_count(const bvh_input *in) {
    const geometry_arrays *g = in->geometry;
    size_t cap = g->sphere_count + g->quad_count + (in->mesh ? in->mesh->triangle_count : 0) + g->instance_count +
                 g->moving_sphere_count;
    for (size_t i = 0; in->flat && i < g->instance_count; i++) cap += in->flat[i] ? in->flat[i]->triangle_count : 0;
    return cap;
}

// The binary tree over bd->prims[0, tree) into b->nodes2, on the pool when it is big; false when out of memory or
// stopped. *used: the references its leaves hold, bd->prims[0, *used) (more than tree where spatial splits cut
// triangles: bd->prims then has grown, the `front` primitives after the tree's moved to follow them).
static bool build_binary(bvh *b, builder *bd, size_t tree, size_t front, thread_pool *pool, size_t parallel_min,
                         size_t *used) {
    // Room for every node the build may make; with spatial splits far more than it will, which costs address space
    // only until the pages are written, and is given back below.
    b->nodes2 = tree ? malloc(bvh_node_room(bd, tree) * sizeof *b->nodes2) : NULL;
    if (tree && !b->nodes2) return false;
    bd->nodes = b->nodes2;
    *used = tree;
    bool built = true;
    int64_t began = bvh_step_began();
    if (tree) {
        if (bd->spatial) built = bvh_build_spatial(bd, tree, front, pool, used);
        else if (pool && tree >= 2 * parallel_min) built = bvh_build_parallel(bd, tree, pool, parallel_min);
        else bvh_build_range(bd, 0, tree, 0, NULL);
    }
    if (!built || bd->stopped || bd->failed) return false;
    if (bd->spatial) {
        bvh2_node *fit = realloc(b->nodes2, bd->node_count * sizeof *fit);
        if (fit) b->nodes2 = bd->nodes = fit;
    }
    bvh_step_traced("BVH binary tree", began);
    return true;
}

// Every step of bvh_build over the input array prims (of input_count(&b->input) places), which it frees or hands
// to b as its references; false when out of memory or stopped (b then holds what bvh_release frees).
static bool build_steps(bvh *b, const accel_build_options *opt, bool wide, build_prim *prims, thread_pool *pool,
                        size_t parallel_min) {
    const bvh_input *in = &b->input;
    box3 all;
    int64_t began = bvh_step_began();
    size_t n = bvh_gather_prims(in, prims, pool, &all, &b->triangles_only);
    bvh_step_traced("BVH boxes", began);
    b->prim_count = n;
    // Where spheres are under a tenth of a mixed tree's primitives, nearly every ray meets triangles, and making
    // their test's constants before the walk takes a division off the path to the first triangle packet (the
    // Cornell box with its glass ball 1.042); book 2's final scene, a third spheres, many of its rays in the
    // smoke-filled ball, is better off making them only when needed (up front: 0.970).
    size_t triangles = 0, spheres = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t k = prims[i].ref.kind;
        triangles += k == PRIM_QUAD || k == PRIM_TRIANGLE;
        spheres += k == PRIM_SPHERE || k == PRIM_MOVING_SPHERE;
    }
    b->triangles_first = triangles > 0 && spheres * 10 < n;
    if (wide && !opt->no_presplit && n > 0) {
        began = bvh_step_began();
        n = bvh_presplit(in, &prims, n, pool);
        bvh_step_traced("BVH pre-split", began);
    }
    if (n == 0) {
        free(prims);
        return true;
    }
    b->bounds = (bounds3){v3(all.lo[0], all.lo[1], all.lo[2]), v3(all.hi[0], all.hi[1], all.hi[2])};
    // The wide BVH tests the huge spheres (the last `front` prims) on their own, the tree holds the rest.
    size_t front = wide && in->geometry->sphere_count ? bvh_split_front(prims, n, &all) : 0, tree = n - front;
    int shift = wide ? (BVH_PACKET == 8 ? 3 : 2) : 0;
    builder bd = {.prims = prims, .block_shift = shift, .block_mask = ((size_t)1 << shift) - 1,
                  .max_leaf = wide ? BVH_PACKET : BIN_MAX_LEAF, .stop = opt->stop};
    // Spatial splits in a wide tree with triangles (bvh_spatial.h).
    bvh_spatial sp = {in};
    if (wide && !opt->no_spatial && triangles > 0) bd.spatial = &sp;
    size_t used;
    bool built = build_binary(b, &bd, tree, front, pool, parallel_min, &used);
    prims = bd.prims; // a spatial build grows it
    if (!built) {
        free(prims);
        return false;
    }
    b->node2_count = bd.node_count;
    b->ref_count = used + front;
    b->refs = bvh_refs_in_place(prims, used + front);
    b->stats.nodes = bd.node_count - bd.leaves;
    b->stats.leaves = bd.leaves;
    b->stats.depth = bd.depth;
    return !wide || bvh_collapse_wide(b, pool, bd.leaves, used, front);
}

bool bvh_build(bvh *b, const bvh_input *in, const accel_build_options *opt, bool wide) {
    static const accel_build_options defaults;
    if (!opt) opt = &defaults;
    bvh_adopt(b, in);
    size_t cap = input_count(&b->input);
    if (cap == 0) return true;
    // Indices must fit their fields.
    if (cap >= BVH_LEAF / 2 || b->input.geometry->instance_count >= PRIM_NO_INSTANCE) return false;
    build_prim *prims = malloc(cap * sizeof *prims);
    if (!prims) return false;
    // Threads for a big build (the same tree for any number): gathering the boxes, the top of the tree, the
    // packets. One thread, or a pool that started fewer than two: serially.
    int threads = opt->threads > 0 ? opt->threads : thread_pool_online_cpus();
    size_t parallel_min = opt->parallel_min ? opt->parallel_min : PARALLEL_MIN;
    thread_pool *pool = threads > 1 && cap >= 2 * parallel_min ? thread_pool_start(threads) : NULL;
    thread_pool *use = pool && thread_pool_size(pool) >= 2 ? pool : NULL;
    bool ok = build_steps(b, opt, wide, prims, use, parallel_min);
    thread_pool_stop(pool); // the pool's one stop, whatever the steps did (NULL: there was none)
    if (!ok) bvh_release(b);
    return ok;
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
