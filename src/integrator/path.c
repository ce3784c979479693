// path.c — the path tracer of "Ray Tracing in One Weekend", iterative: a path traces at most max_depth
// rays, each surface scatters it by its material (material/scatter.h), and escaping rays see the
// background. Point and directional lights are added at diffuse surfaces by next-event estimation.
#include "integrator/integrator.h"
#include "material/scatter.h"

#include <math.h>

// Spawned-ray offset, relative to the magnitudes that set the float error of a sphere hit: the point's
// coordinates (rounding of the re-projected point) and the radius (rounding of o - c and of |o - c|^2 - r^2
// in sphere_intersect, which misplace the origin by about 3 * 2^-24 r). 2^-21 is 2.7 times that bound, and
// 8 times the smallest factor with which no ray re-hit its own sphere on the book's final scene.
static const float path_offset_rel = 0x1p-21f;

// The hit point moved onto the sphere in double precision, so that its only error is the final rounding
// to float: p = c + (p - c) |r| / |p - c| (pbrt's re-projection).
static vec3 sphere_reproject(const sphere *sp, vec3 p) {
    double q[3] = {(double)p.x - sp->center.x, (double)p.y - sp->center.y, (double)p.z - sp->center.z};
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (!(len > 0.0)) return p;
    double k = fabs((double)sp->radius) / len;
    return v3((float)(sp->center.x + q[0] * k), (float)(sp->center.y + q[1] * k), (float)(sp->center.z + q[2] * k));
}

// Bound on how far the surface point (and the surface as sphere_intersect sees it) is off, along the normal.
static float sphere_offset(const sphere *sp, vec3 p) {
    // Plain comparisons: fmaxf is a libm call at -O3 without -ffinite-math-only, four per bounce.
    float ax = fabsf(p.x), ay = fabsf(p.y), az = fabsf(p.z);
    float pmax = ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
    return path_offset_rel * (pmax + fabsf(sp->radius)) + 1e-30f;
}

// A ray leaving point p along unit dir, its origin pushed off the surface (unit normal n, error bound
// err) to the side dir goes, so that it cannot re-hit this surface.
static ray spawn_ray(vec3 p, vec3 n, float err, vec3 dir, float tmax) {
    ray out;
    out.o = v3_fma(p, n, v3_dot(dir, n) >= 0.0f ? err : -err);
    out.d = dir;
    out.tmin = 0.0f;
    out.tmax = tmax;
    return out;
}

// Direct light from the scene's point and directional lights at a diffuse surface point: BRDF (weight / pi)
// times irradiance, unoccluded. Point lights fall off with the inverse square of the distance; a
// directional light's intensity is the irradiance it gives a surface facing it. Ambient lights have no
// place in a path tracer (the background is the ambient light) and are ignored.
static vec3 direct_light(const glint_scene *s, vec3 p, vec3 n, float err, vec3 weight, thread_stats *ts) {
    const float inv_pi = 0.318309886183791f;
    vec3 sum = v3s(0.0f);
    for (size_t i = 0; i < s->light_count; i++) {
        const light *l = &s->lights[i];
        vec3 wl;
        float dist, falloff;
        if (l->kind == LIGHT_POINT) {
            vec3 to = v3_sub(l->position, p);
            float d2 = v3_len2(to);
            if (!(d2 > 0.0f)) continue;
            dist = sqrtf(d2);
            wl = v3_scale(to, 1.0f / dist);
            falloff = 1.0f / d2;
        } else if (l->kind == LIGHT_DIRECTIONAL) {
            if (!(v3_len2(l->direction) > 0.0f)) continue;
            wl = v3_unit(l->direction);
            dist = INFINITY;
            falloff = 1.0f;
        } else {
            continue;
        }
        float cos_l = v3_dot(n, wl);
        if (!(cos_l > 0.0f)) continue;
        // Stop just short of a point light: whatever lies beyond it casts no shadow.
        ray shadow = spawn_ray(p, n, err, wl, dist * (1.0f - 0x1p-20f));
        ts->shadow_rays++;
        if (accel_occluded(s->accel, &shadow)) continue;
        sum = v3_add(sum, v3_scale(l->intensity, cos_l * falloff));
    }
    return v3_scale(v3_mul(sum, weight), inv_pi);
}

vec3 path_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts) {
    (void)sample;
    float fx, fy;
    integrator_film_point(s, x, y, r, &fx, &fy);
    ray cur = camera_ray(&s->camera, fx, fy, r);
    vec3 radiance = v3s(0.0f), throughput = v3s(1.0f);
    bool has_lights = s->light_count > 0;
    for (int depth = 0; depth < s->settings.max_depth; depth++) {
        hit h;
        ts->rays++;
        if (!accel_intersect(s->accel, &cur, &h)) {
            radiance = v3_add(radiance, v3_mul(throughput, scene_background(&s->settings, cur.d)));
            break;
        }
        surface sf = surface_at(s, &cur, &h);
        const material *m = &s->materials[sf.material];
        radiance = v3_add(radiance, v3_mul(throughput, mat_emitted(m, sf.front)));
        scatter_event ev;
        if (!mat_scatter(m, cur.d, sf.n, sf.front, r, &ev)) break;
        const sphere *sp = &s->spheres[h.prim];
        vec3 p = sphere_reproject(sp, sf.p);
        float err = sphere_offset(sp, p);
        if (has_lights && ev.diffuse)
            radiance = v3_add(radiance, v3_mul(throughput, direct_light(s, p, sf.n, err, ev.weight, ts)));
        throughput = v3_mul(throughput, ev.weight);
        // A black throughput can gain nothing more: end the path without tracing the rest.
        if (!(throughput.x > 0.0f || throughput.y > 0.0f || throughput.z > 0.0f)) break;
        cur = spawn_ray(p, sf.n, err, ev.dir, INFINITY);
    }
    return radiance;
}
