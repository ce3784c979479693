// accel.c — the acceleration structure's front door: the wide SIMD BVH, the binary BVH, or `none`,
// which tests every primitive (for testing).
#include "accel/accel.h"
#include "accel/bvh.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

struct accel {
    accel_kind kind;
    const sphere *spheres;
    size_t sphere_count;
    bvh bvh;
    accel_stats stats;
};

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

accel *accel_build(const glint_scene *s, glint_error *err) {
    double t0 = now_seconds();
    accel *a = calloc(1, sizeof *a);
    if (!a) {
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    a->kind = s->settings.accel;
    a->spheres = s->spheres;
    a->sphere_count = s->sphere_count;
    if (a->kind != ACCEL_NONE) {
        if (!bvh_build(&a->bvh, s->spheres, s->sphere_count, a->kind == ACCEL_BVH)) {
            free(a);
            snprintf(err->message, sizeof err->message,
                     "out of memory building the BVH over %zu spheres", s->sphere_count);
            return NULL;
        }
        a->stats = a->bvh.stats;
    }
    a->stats.build_seconds = now_seconds() - t0;
    return a;
}

void accel_free(accel *a) {
    if (!a) return;
    if (a->kind != ACCEL_NONE) bvh_release(&a->bvh);
    free(a);
}

void accel_get_stats(const accel *a, accel_stats *out) { *out = a->stats; }

// Brute force: every sphere, in index order; ties keep the lower index.
static bool brute_intersect(const accel *a, const ray *r, hit *h) {
    float tmax = r->tmax;
    bool found = false;
    for (size_t i = 0; i < a->sphere_count; i++) {
        float t;
        if (sphere_intersect(a->spheres[i].center, a->spheres[i].radius, r, r->tmin, tmax, &t)) {
            tmax = t;
            bvh_sphere_hit(h, t, (uint32_t)i);
            found = true;
        }
    }
    return found;
}

static bool brute_occluded(const accel *a, const ray *r) {
    for (size_t i = 0; i < a->sphere_count; i++) {
        float t;
        if (sphere_intersect(a->spheres[i].center, a->spheres[i].radius, r, r->tmin, r->tmax, &t)) return true;
    }
    return false;
}

bool accel_intersect(const accel *a, const ray *r, hit *h) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_intersect(&a->bvh, r, h);
    case ACCEL_BVH2: return bvh2_intersect(&a->bvh, r, h);
    case ACCEL_NONE: return brute_intersect(a, r, h);
    }
    return false;
}

void accel_intersect2(const accel *a, const ray r[2], hit h[2], bool found[2]) {
    if (a->kind == ACCEL_BVH) {
        bvh_intersect2(&a->bvh, &r[0], &r[1], &h[0], &h[1], &found[0], &found[1]);
        return;
    }
    found[0] = accel_intersect(a, &r[0], &h[0]);
    found[1] = accel_intersect(a, &r[1], &h[1]);
}

bool accel_occluded(const accel *a, const ray *r) {
    switch (a->kind) {
    case ACCEL_BVH: return bvh_occluded(&a->bvh, r);
    case ACCEL_BVH2: return bvh2_occluded(&a->bvh, r);
    case ACCEL_NONE: return brute_occluded(a, r);
    }
    return false;
}
