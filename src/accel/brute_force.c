// brute_force.c — every primitive tested against every ray: the reference every BVH is checked against, and
// the structure --accel none selects.
#include "accel/brute_force.h"
#include "accel/bvh_kernel.h"

// Every primitive of in, in the same order of precedence as the BVHs (bvh_better).
static bool brute_force_run(const geometry_arrays *in, const mesh *const *flat, const ray *r, hit *best, bool any) {
    if (ray_is_nan(r)) return false;
    tri_cache tc = {.ready = false};
    bool found = false;
    for (size_t i = 0; i < in->sphere_count; i++) {
        float t;
        if (!sphere_intersect(in->spheres[i].center, in->spheres[i].radius, r, r->tmin, r->tmax, &t)) continue;
        if (any) return true;
        found = true;
        offer(best, (hit){t, (uint32_t)i, HIT_SPHERE, HIT_NO_INSTANCE, 0.0f, 0.0f});
    }
    for (size_t i = 0; i < in->quad_count; i++) {
        quad_hit qh;
        if (!quad_intersect(&in->quads[i], tri_for(&tc, r), r->tmin, r->tmax, &qh)) continue;
        if (any) return true;
        found = true;
        offer(best, (hit){qh.t, (uint32_t)i, HIT_QUAD, HIT_NO_INSTANCE, qh.alpha, qh.beta});
    }
    for (size_t i = 0; i < in->moving_sphere_count; i++) {
        vec3 c = moving_sphere_center(&in->moving_spheres[i], r->time);
        float t;
        if (!sphere_intersect(c, in->moving_spheres[i].radius, r, r->tmin, r->tmax, &t)) continue;
        if (any) return true;
        found = true;
        offer(best, (hit){t, (uint32_t)i, HIT_MOVING_SPHERE, HIT_NO_INSTANCE, 0.0f, 0.0f});
    }
    for (size_t i = 0; i < in->instance_count; i++) {
        const instance *inst = &in->instances[i];
        if (flat && flat[i]) { // in world space
            for (size_t k = 0; k < flat[i]->triangle_count; k++) {
                tri_hit th;
                if (!mesh_intersect_triangle(flat[i], k, tri_for(&tc, r), r->tmin, r->tmax, &th)) continue;
                if (any) return true;
                found = true;
                offer(best, (hit){th.t, (uint32_t)k, HIT_TRIANGLE, (uint32_t)i, th.b1, th.b2});
            }
            continue;
        }
        transform moved; // a moving instance's transform at the ray's time
        if (inst->motion) motion_at(&in->motions[inst->motion - 1], r->time, &moved);
        ray o = mat4_apply_ray(inst->motion ? &moved.inv : &inst->xf.inv, r);
        if (inst->kind == INSTANCE_SPHERE) {
            const sphere *sp = &in->instance_spheres[inst->index];
            float t;
            if (!sphere_intersect(sp->center, sp->radius, &o, o.tmin, o.tmax, &t)) continue;
            if (any) return true;
            found = true;
            offer(best, (hit){t, inst->index, HIT_SPHERE, (uint32_t)i, 0.0f, 0.0f});
            continue;
        }
        const mesh *m = in->meshes[inst->index];
        tri_ray otr = tri_ray_make(&o);
        for (size_t k = 0; k < m->triangle_count; k++) {
            tri_hit th;
            if (!mesh_intersect_triangle(m, k, &otr, o.tmin, o.tmax, &th)) continue;
            if (any) return true;
            found = true;
            offer(best, (hit){th.t, (uint32_t)k, HIT_TRIANGLE, (uint32_t)i, th.b1, th.b2});
        }
    }
    return found;
}

bool brute_force_intersect(const geometry_arrays *in, const mesh *const *flat, const ray *r, hit *h) {
    hit best = bvh_no_hit(r);
    if (!brute_force_run(in, flat, r, &best, false)) return false;
    *h = best;
    return true;
}

bool brute_force_occluded(const geometry_arrays *in, const mesh *const *flat, const ray *r) {
    hit best = bvh_no_hit(r);
    return brute_force_run(in, flat, r, &best, true);
}
