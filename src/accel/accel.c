// accel.c — the acceleration structure's front door: the wide SIMD BVH, the binary BVH, or `none`,
// which tests every primitive (for testing). Meshes get a BVH each, shared by all their instances; the
// world BVH holds spheres, quads and instances.
#include "accel/accel.h"
#include "core/clock.h"
#include "accel/bvh.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>

// Quads, meshes and instances go into the BVH only once the integrators' surface_at turns their hits
// (hit.kind, instance, b1, b2) into shading data; until then a non-sphere hit would index the spheres.
// The BVH and its tests handle every kind already (tests/test_bvh.c, check_mixed).
#ifndef ACCEL_ALL_KINDS
#define ACCEL_ALL_KINDS 1
#endif

struct accel {
    accel_kind kind;
    bvh_input input; ///< the primitives (brute force tests them directly)
    bvh world;
    bvh *blas;       ///< one per scene mesh
    size_t blas_count;
    accel_stats stats;
};

accel *accel_build(const glint_scene *s, glint_error *err) {
    double t0 = clock_seconds();
    accel *a = calloc(1, sizeof *a);
    if (!a) {
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    a->kind = s->settings.accel;
    a->input = (bvh_input){.spheres = s->spheres, .sphere_count = s->sphere_count};
    size_t mesh_count = 0;
    if (ACCEL_ALL_KINDS) {
        a->input.quads = s->quads;
        a->input.quad_count = s->quad_count;
        a->input.instances = s->instances;
        a->input.instance_count = s->instance_count;
        a->input.meshes = s->meshes;
        a->input.instance_spheres = s->instance_spheres;
        mesh_count = s->mesh_count;
    }
    if (a->kind != ACCEL_NONE) {
        bool wide = a->kind == ACCEL_BVH, ok = true;
        a->blas = mesh_count ? calloc(mesh_count, sizeof *a->blas) : NULL;
        ok = !mesh_count || a->blas;
        for (size_t i = 0; ok && i < mesh_count; i++, a->blas_count++) {
            bvh_input mi = {.mesh = &s->meshes[i].geometry};
            ok = bvh_build(&a->blas[i], &mi, wide);
            a->stats.nodes += a->blas[i].stats.nodes;
            a->stats.leaves += a->blas[i].stats.leaves;
            if (a->blas[i].stats.depth > a->stats.depth) a->stats.depth = a->blas[i].stats.depth;
        }
        a->input.blas = a->blas;
        ok = ok && bvh_build(&a->world, &a->input, wide);
        if (!ok) {
            accel_free(a);
            snprintf(err->message, sizeof err->message, "out of memory building the BVH");
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
    free(a);
}

void accel_get_stats(const accel *a, accel_stats *out) { *out = a->stats; }

bool accel_intersect(const accel *a, const ray *r, hit *h) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_intersect(&a->world, r, h);
    case ACCEL_BVH2: return bvh2_intersect(&a->world, r, h);
    case ACCEL_NONE: return bvh_brute_intersect(&a->input, r, h);
    }
    return false;
}

void accel_intersect2(const accel *a, const ray r[2], hit h[2], bool found[2]) {
    if (a->kind == ACCEL_BVH) {
        bvh_intersect2(&a->world, &r[0], &r[1], &h[0], &h[1], &found[0], &found[1]);
        return;
    }
    found[0] = accel_intersect(a, &r[0], &h[0]);
    found[1] = accel_intersect(a, &r[1], &h[1]);
}

bool accel_occluded(const accel *a, const ray *r) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_occluded(&a->world, r);
    case ACCEL_BVH2: return bvh2_occluded(&a->world, r);
    case ACCEL_NONE: return bvh_brute_occluded(&a->input, r);
    }
    return false;
}
