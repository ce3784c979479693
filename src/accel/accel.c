// accel.c — the acceleration structure's front door: the wide SIMD BVH, the binary BVH, or `none`, which
// tests every primitive. A mesh placed once, and still, is flattened: its triangles, in world space, join
// the world BVH (a ray through it crosses one tree and is never moved to object space). A mesh placed several
// times, or moving, gets a BVH of its own, shared by its instances; the world BVH holds those instances, with
// spheres and quads.
#include "accel/accel.h"
#include "accel/brute_force.h"
#include "accel/bvh.h"
#include "core/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct accel {
    accel_kind kind;
    geometry_arrays geometry; ///< the value built over (brute force tests it, the BVHs point at it); meshes: mesh_list
    const mesh **mesh_list;   ///< the value's list of meshes, copied: the caller's may go once the build is done
    size_t stream_min_bytes;  ///< accel_streams' smallest world BVH (the option, or ACCEL_STREAM_MIN_BYTES)
    size_t interleave_min_bytes; ///< accel_interleaves' smallest world BVH (the option, or ACCEL_INTERLEAVE_MIN_BYTES)
    bvh world;
    bvh *blas;             ///< one per mesh (empty for a mesh that is only flattened)
    size_t blas_count;
    mesh *flat_meshes;     ///< per instance: its mesh with positions in world space when flattened, else zeroed
    const mesh **flat;     ///< per instance: &flat_meshes[i] when flattened, else NULL (NULL: none is)
    accel_stats stats;
};

// Whether instance i is flattened: a still mesh placed by no other instance. Its triangles then cost no
// more memory in the world BVH than in a BVH of their own, and rays skip the second tree and the transform.
static bool flattens(const geometry_arrays *in, const uint32_t *placements, size_t i) {
    const instance *inst = &in->instances[i];
    return inst->kind == INSTANCE_MESH && inst->motion == 0 && placements[inst->index] == 1;
}

// Fills a->flat_meshes and a->flat for the instances that flattens() picks: the mesh's arrays shared, its
// positions transformed to world space (each vertex once, so triangles that share it still share it exactly
// and the mesh stays watertight). False when out of memory.
static bool flatten_instances(accel *a, const geometry_arrays *in) {
    if (in->instance_count == 0) return true;
    uint32_t *placements = calloc(in->mesh_count ? in->mesh_count : 1, sizeof *placements);
    a->flat_meshes = calloc(in->instance_count, sizeof *a->flat_meshes);
    a->flat = calloc(in->instance_count, sizeof *a->flat);
    bool ok = placements && a->flat_meshes && a->flat;
    for (size_t i = 0; ok && i < in->instance_count; i++)
        if (in->instances[i].kind == INSTANCE_MESH) placements[in->instances[i].index]++;
    bool any = false;
    for (size_t i = 0; ok && i < in->instance_count; i++) {
        if (!flattens(in, placements, i)) continue;
        const mesh *m = in->meshes[in->instances[i].index];
        mesh *w = &a->flat_meshes[i];
        *w = *m;
        w->positions = malloc((m->position_count ? m->position_count : 1) * sizeof *w->positions);
        if (!w->positions) {
            ok = false;
            break;
        }
        for (size_t k = 0; k < m->position_count; k++)
            w->positions[k] = mat4_apply_point(&in->instances[i].xf.m, m->positions[k]);
        a->flat[i] = w;
        any = true;
    }
    free(placements);
    if (ok && !any) { // nothing flattened: the structures need not look
        free(a->flat_meshes);
        free(a->flat);
        a->flat_meshes = NULL;
        a->flat = NULL;
    }
    return ok;
}

// Whether mesh i has an instance that is not flattened (only those need the mesh's own BVH).
static bool mesh_needs_blas(const accel *a, const geometry_arrays *in, size_t i) {
    for (size_t k = 0; k < in->instance_count; k++)
        if (in->instances[k].kind == INSTANCE_MESH && in->instances[k].index == i && !(a->flat && a->flat[k]))
            return true;
    return false;
}

const char *const accel_kind_names[ACCEL_KIND_COUNT] = {"bvh", "bvh2", "none"};

// A new accel over its own copy of the value *g (and of g's list of meshes), with nothing built yet; NULL when
// out of memory.
static accel *accel_new(const geometry_arrays *g, accel_kind kind, const accel_build_options *opt) {
    accel *a = calloc(1, sizeof *a);
    const mesh **meshes = g->mesh_count ? malloc(g->mesh_count * sizeof *meshes) : NULL;
    if (!a || (g->mesh_count && !meshes)) {
        free(a);
        free(meshes);
        return NULL;
    }
    if (g->mesh_count) memcpy(meshes, g->meshes, g->mesh_count * sizeof *meshes);
    a->kind = kind;
    a->geometry = *g;
    a->geometry.meshes = a->mesh_list = meshes;
    a->stream_min_bytes = opt->stream_min_bytes ? opt->stream_min_bytes : ACCEL_STREAM_MIN_BYTES;
    a->interleave_min_bytes = opt->interleave_min_bytes ? opt->interleave_min_bytes : ACCEL_INTERLEAVE_MIN_BYTES;
    return a;
}

// The BVHs of a (wide or binary): one per mesh that an instance places unflattened, then the world's over
// a->geometry; false when out of memory or stopped.
static bool accel_build_bvhs(accel *a, const accel_build_options *opt) {
    const geometry_arrays *g = &a->geometry;
    bool wide = a->kind == ACCEL_BVH;
    a->blas = g->mesh_count ? calloc(g->mesh_count, sizeof *a->blas) : NULL;
    bool ok = !g->mesh_count || a->blas;
    for (size_t i = 0; ok && i < g->mesh_count; i++, a->blas_count++) {
        if (!mesh_needs_blas(a, g, i)) continue;
        ok = bvh_build(&a->blas[i], &(bvh_input){.mesh = g->meshes[i]}, opt, wide);
        a->stats.nodes += a->blas[i].stats.nodes;
        a->stats.leaves += a->blas[i].stats.leaves;
        if (a->blas[i].stats.depth > a->stats.depth) a->stats.depth = a->blas[i].stats.depth;
    }
    bvh_input world = {.geometry = g, .blas = a->blas, .flat = (const mesh *const *)a->flat};
    ok = ok && bvh_build(&a->world, &world, opt, wide);
    // Counts add up over the world BVH and the meshes' BVHs; depth is the world's plus the deepest mesh's.
    a->stats.nodes += a->world.stats.nodes;
    a->stats.leaves += a->world.stats.leaves;
    a->stats.depth += a->world.stats.depth;
    return ok;
}

accel *accel_build(const geometry_arrays *g, accel_kind kind, const accel_build_options *opt, glint_error *err) {
    static const accel_build_options defaults;
    if (!opt) opt = &defaults;
    double t0 = clock_seconds();
    accel *a = accel_new(g, kind, opt);
    if (!a || !flatten_instances(a, &a->geometry)) {
        accel_free(a);
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    if (kind != ACCEL_NONE && !accel_build_bvhs(a, opt)) {
        accel_free(a);
        bool stopped = opt->stop && atomic_load(opt->stop);
        snprintf(err->message, sizeof err->message, "%s",
                 stopped ? "interrupted while building the BVH" : "out of memory building the BVH");
        return NULL;
    }
    a->stats.build_seconds = clock_seconds() - t0;
    return a;
}

void accel_free(accel *a) {
    if (!a) return;
    bvh_release(&a->world);
    for (size_t i = 0; i < a->blas_count; i++) bvh_release(&a->blas[i]);
    free(a->blas);
    for (size_t i = 0; a->flat && i < a->geometry.instance_count; i++) free(a->flat_meshes[i].positions);
    free(a->flat_meshes);
    free(a->flat);
    free(a->mesh_list);
    free(a);
}

void accel_get_stats(const accel *a, accel_stats *out) { *out = a->stats; }

bool accel_intersect(const accel *a, const ray *r, hit *h) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_intersect(&a->world, r, h);
    case ACCEL_BVH2: return bvh2_intersect(&a->world, r, h);
    case ACCEL_NONE: return brute_force_intersect(&a->geometry, (const mesh *const *)a->flat, r, h);
    }
    return false;
}

_Static_assert((int)ACCEL_COHERENT <= (int)BVH_COHERENT, "the packets the BVH takes");

bool accel_coherent(const accel *a) { return a->kind == ACCEL_BVH && bvh_coherent(&a->world); }

void accel_intersect_coherent(const accel *a, int n, const ray *rays, hit *hits, bool *found) {
    if (accel_coherent(a)) bvh_intersect_coherent(&a->world, n, rays, hits, found);
    else
        for (int i = 0; i < n; i++) found[i] = accel_intersect(a, &rays[i], &hits[i]);
}

// The world BVH's nodes and leaf packets, in bytes: what a traversal may read.
static size_t world_bytes(const accel *a) {
    return a->world.wnode_count * sizeof(bvh_wnode) + a->world.slot_count * sizeof(bvh_slot);
}

bool accel_streams(const accel *a) {
    return a->kind == ACCEL_BVH && bvh_streams(&a->world) && world_bytes(a) >= a->stream_min_bytes;
}

bool accel_interleaves(const accel *a) {
    return accel_streams(a) && world_bytes(a) >= a->interleave_min_bytes;
}

void accel_intersect_stream(const accel *a, int n, const ray *rays, hit *hits, bool *found) {
    switch (a->kind) {
    case ACCEL_BVH:
        if (accel_interleaves(a)) bvh_intersect_stream(&a->world, n, rays, hits, found);
        else
            for (int i = 0; i < n; i++) found[i] = bvh_intersect(&a->world, &rays[i], &hits[i]);
        return;
    case ACCEL_BVH2:
        for (int i = 0; i < n; i++) found[i] = bvh2_intersect(&a->world, &rays[i], &hits[i]);
        return;
    case ACCEL_NONE:
        for (int i = 0; i < n; i++)
            found[i] = brute_force_intersect(&a->geometry, (const mesh *const *)a->flat, &rays[i], &hits[i]);
        return;
    }
}

_Static_assert(ACCEL_NO_OCCLUDER == BVH_EMPTY, "the BVH keeps its no-leaf value in the caller's occluder");

bool accel_occluded(const accel *a, const ray *r) { return accel_occluded_hinted(a, r, NULL); }

bool accel_occluded_hinted(const accel *a, const ray *r, uint32_t *occluder) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_occluded(&a->world, r, occluder);
    case ACCEL_BVH2: return bvh2_occluded(&a->world, r);
    case ACCEL_NONE: return brute_force_occluded(&a->geometry, (const mesh *const *)a->flat, r);
    }
    return false;
}
