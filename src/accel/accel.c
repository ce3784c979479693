// accel.c — the acceleration structure's front door; `none` tests every primitive (for testing).
#include "accel/accel.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

struct accel {
    accel_kind kind;
    const sphere *spheres;
    size_t sphere_count;
    accel_stats stats;
};

accel *accel_build(const glint_scene *s, glint_error *err) {
    accel *a = calloc(1, sizeof *a);
    if (!a) {
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    a->kind = s->settings.accel;
    a->spheres = s->spheres;
    a->sphere_count = s->sphere_count;
    return a;
}

void accel_free(accel *a) { free(a); }

void accel_get_stats(const accel *a, accel_stats *out) { *out = a->stats; }

bool accel_intersect(const accel *a, const ray *r, hit *h) {
    float tmax = r->tmax;
    bool found = false;
    for (size_t i = 0; i < a->sphere_count; i++) {
        float t;
        if (sphere_intersect(a->spheres[i].center, a->spheres[i].radius, r, r->tmin, tmax, &t)) {
            tmax = t;
            h->t = t;
            h->prim = (uint32_t)i;
            found = true;
        }
    }
    return found;
}

bool accel_occluded(const accel *a, const ray *r) {
    for (size_t i = 0; i < a->sphere_count; i++) {
        float t;
        if (sphere_intersect(a->spheres[i].center, a->spheres[i].radius, r, r->tmin, r->tmax, &t)) return true;
    }
    return false;
}
