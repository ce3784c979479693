// accel.c — the acceleration structure's front door: the wide SIMD BVH, the binary BVH, or `none`, which
// tests every primitive. Meshes get a BVH each, shared by all their instances; the world BVH holds spheres,
// quads and instances.
#include "accel/accel.h"
#include "accel/brute_force.h"
#include "accel/bvh.h"
#include "core/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct accel {
    accel_kind kind;
    accel_input input;     ///< the primitives (brute force tests them directly); its `meshes` is mesh_list
    const mesh **mesh_list; ///< the input's list of meshes, copied: the caller's may go once the build is done
    bvh world;
    bvh *blas;             ///< one per mesh
    size_t blas_count;
    accel_stats stats;
};

accel *accel_build(const accel_input *in, accel_kind kind, glint_error *err) {
    double t0 = clock_seconds();
    accel *a = calloc(1, sizeof *a);
    const mesh **meshes = in->mesh_count ? malloc(in->mesh_count * sizeof *meshes) : NULL;
    if (!a || (in->mesh_count && !meshes)) {
        free(a);
        free(meshes);
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    if (in->mesh_count) memcpy(meshes, in->meshes, in->mesh_count * sizeof *meshes);
    a->kind = kind;
    a->input = *in;
    a->input.meshes = a->mesh_list = meshes;
    if (kind != ACCEL_NONE) {
        bool wide = kind == ACCEL_BVH;
        a->blas = in->mesh_count ? calloc(in->mesh_count, sizeof *a->blas) : NULL;
        bool ok = !in->mesh_count || a->blas;
        for (size_t i = 0; ok && i < in->mesh_count; i++, a->blas_count++) {
            bvh_input mi = {.mesh = meshes[i], .stop = in->stop, .threads = in->threads};
            ok = bvh_build(&a->blas[i], &mi, wide);
            a->stats.nodes += a->blas[i].stats.nodes;
            a->stats.leaves += a->blas[i].stats.leaves;
            if (a->blas[i].stats.depth > a->stats.depth) a->stats.depth = a->blas[i].stats.depth;
        }
        bvh_input world = {.spheres = in->spheres,
                           .sphere_count = in->sphere_count,
                           .quads = in->quads,
                           .quad_count = in->quad_count,
                           .instances = in->instances,
                           .instance_count = in->instance_count,
                           .blas = a->blas,
                           .instance_spheres = in->instance_spheres,
                           .moving_spheres = in->moving_spheres,
                           .moving_sphere_count = in->moving_sphere_count,
                           .motions = in->motions,
                           .time0 = in->time0,
                           .time1 = in->time1,
                           .stop = in->stop,
                           .threads = in->threads};
        ok = ok && bvh_build(&a->world, &world, wide);
        if (!ok) {
            accel_free(a);
            bool stopped = in->stop && atomic_load(in->stop);
            snprintf(err->message, sizeof err->message, "%s",
                     stopped ? "interrupted while building the BVH" : "out of memory building the BVH");
            return NULL;
        }
        // Counts add up over the world BVH and the meshes' BVHs; depth is the world's plus the deepest mesh's.
        a->stats.nodes += a->world.stats.nodes;
        a->stats.leaves += a->world.stats.leaves;
        a->stats.depth += a->world.stats.depth;
    }
    a->stats.build_seconds = clock_seconds() - t0;
    return a;
}

void accel_free(accel *a) {
    if (!a) return;
    bvh_release(&a->world);
    for (size_t i = 0; i < a->blas_count; i++) bvh_release(&a->blas[i]);
    free(a->blas);
    free(a->mesh_list);
    free(a);
}

void accel_get_stats(const accel *a, accel_stats *out) { *out = a->stats; }

bool accel_intersect(const accel *a, const ray *r, hit *h) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_intersect(&a->world, r, h);
    case ACCEL_BVH2: return bvh2_intersect(&a->world, r, h);
    case ACCEL_NONE: return brute_force_intersect(&a->input, r, h);
    }
    return false;
}

bool accel_occluded(const accel *a, const ray *r) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_occluded(&a->world, r);
    case ACCEL_BVH2: return bvh2_occluded(&a->world, r);
    case ACCEL_NONE: return brute_force_occluded(&a->input, r);
    }
    return false;
}
