// bvh_build.c — the BVH build's entry point (bvh_build) and the order of its steps: the input (bvh_gather.c), the
// binary tree by the serial binned SAH (bvh_sah.c) or on every thread (bvh_build_parallel.c), then the wide
// collapse and its leaf packets (bvh_collapse.c).
#include "accel/bvh_build_parallel.h"
#include "accel/bvh_collapse.h"
#include "accel/bvh_gather.h"
#include "accel/bvh_sah.h"

#include <stdlib.h>

// Largest leaf of the binary BVH (its leaves are tested one primitive at a time).
enum { BIN_MAX_LEAF = 4 };

// Points b at in's primitive arrays, with nothing built yet.
static void bvh_adopt(bvh *b, const bvh_input *in) {
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
}

// The primitives in's arrays hold before pre-splitting: the length of the build's input array.
static size_t input_count(const bvh_input *in) {
    size_t cap = in->sphere_count + in->quad_count + (in->mesh ? in->mesh->triangle_count : 0) + in->instance_count +
                 in->moving_sphere_count;
    for (size_t i = 0; in->flat && i < in->instance_count; i++) cap += in->flat[i] ? in->flat[i]->triangle_count : 0;
    return cap;
}

// The binary tree over bd->prims[0, tree) into b->nodes2, on the pool when it is big; false when out of memory or
// stopped.
static bool build_binary(bvh *b, builder *bd, size_t tree, thread_pool *pool, size_t parallel_min) {
    b->nodes2 = tree ? malloc((2 * tree - 1) * sizeof *b->nodes2) : NULL;
    if (tree && !b->nodes2) return false;
    bd->nodes = b->nodes2;
    bool built = true;
    int64_t began = bvh_step_began();
    if (tree) {
        if (pool && tree >= 2 * parallel_min) built = bvh_build_parallel(bd, tree, pool, parallel_min);
        else bvh_build_range(bd, 0, tree, 0, NULL);
    }
    if (!built || bd->stopped) return false;
    bvh_step_traced("BVH binary tree", began);
    return true;
}

// Every step of bvh_build over the input array prims (of input_count(in) places), which it frees or hands to b
// as its references; false when out of memory or stopped (b then holds what bvh_release frees).
static bool build_steps(bvh *b, const bvh_input *in, bool wide, build_prim *prims, thread_pool *pool,
                        size_t parallel_min) {
    box3 all;
    int64_t began = bvh_step_began();
    size_t n = bvh_gather_prims(in, prims, pool, &all, &b->triangles_only);
    bvh_step_traced("BVH boxes", began);
    b->prim_count = n;
    if (wide && !in->no_presplit && n > 0) {
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
    size_t front = wide && in->sphere_count ? bvh_split_front(prims, n, &all) : 0, tree = n - front;
    int shift = wide ? (BVH_PACKET == 8 ? 3 : 2) : 0;
    builder bd = {.prims = prims, .block_shift = shift, .block_mask = ((size_t)1 << shift) - 1,
                  .max_leaf = wide ? BVH_PACKET : BIN_MAX_LEAF, .stop = in->stop};
    if (!build_binary(b, &bd, tree, pool, parallel_min)) {
        free(prims);
        return false;
    }
    b->node2_count = bd.node_count;
    b->ref_count = n;
    b->refs = bvh_refs_in_place(prims, n);
    b->stats.nodes = bd.node_count - bd.leaves;
    b->stats.leaves = bd.leaves;
    b->stats.depth = bd.depth;
    return !wide || bvh_collapse_wide(b, pool, bd.leaves, tree, front);
}

bool bvh_build(bvh *b, const bvh_input *in, bool wide) {
    bvh_adopt(b, in);
    size_t cap = input_count(in);
    if (cap == 0) return true;
    if (cap >= BVH_LEAF / 2 || in->instance_count >= PRIM_NO_INSTANCE) return false; // indices must fit their fields
    build_prim *prims = malloc(cap * sizeof *prims);
    if (!prims) return false;
    // Threads for a big build (the same tree for any number): gathering the boxes, the top of the tree, the
    // packets. One thread, or a pool that started fewer than two: serially.
    int threads = in->threads > 0 ? in->threads : thread_pool_online_cpus();
    size_t parallel_min = in->parallel_min ? in->parallel_min : PARALLEL_MIN;
    thread_pool *pool = threads > 1 && cap >= 2 * parallel_min ? thread_pool_start(threads) : NULL;
    thread_pool *use = pool && thread_pool_size(pool) >= 2 ? pool : NULL;
    bool ok = build_steps(b, in, wide, prims, use, parallel_min);
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
