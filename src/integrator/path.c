// path.c — the path tracer of "Ray Tracing in One Weekend", iterative: a path traces at most max_depth
// rays, each surface scatters it by its material (material/scatter.h), and escaping rays see the
// background. At diffuse surfaces, point and directional lights are added by next-event estimation, and so
// are emissive quads, combined with the BSDF samples that hit them by multiple importance sampling.
#include "integrator/integrator.h"
#include "integrator/spawn.h"
#include "material/scatter.h"

#include <math.h>
#include <stdlib.h>

static const float inv_pi = 0.318309886183791f;

/// The scene's emissive quads, indexed for next-event estimation (built by path_prepare).
struct path_lights {
    uint32_t *quads;   ///< indices into s->quads of the quads that are lights
    float *cdf;        ///< cdf[i]: probability of choosing one of quads[0..i]; the last is 1
    float *select_pdf; ///< per scene quad: probability of choosing it, 0 for a quad that is not a light
    size_t count;      ///< lights
    size_t quad_count; ///< scene quads when indexed (select_pdf's length)
};

void path_release(glint_scene *s) {
    path_lights *pl = s->path_lights;
    if (!pl) return;
    free(pl->quads);
    free(pl->cdf);
    free(pl->select_pdf);
    free(pl);
    s->path_lights = NULL;
}

// A quad light's power up to constant factors (area times mean emission), by which lights are chosen;
// 0 for a quad that emits nothing. Emission textures scale this, but any positive choice stays unbiased.
static double quad_light_power(const glint_scene *s, const quad *q) {
    const material *m = &s->materials[q->material];
    if (m->kind != MAT_DIFFUSE_LIGHT) return 0.0;
    double e = (double)m->emission.x + m->emission.y + m->emission.z;
    double p = e * q->area;
    return isfinite(p) && p > 0.0 ? p : 0.0;
}

bool path_prepare(glint_scene *s) {
    path_release(s);
    size_t count = 0;
    double total = 0.0;
    for (size_t i = 0; i < s->quad_count; i++) {
        double p = quad_light_power(s, &s->quads[i]);
        count += p > 0.0;
        total += p;
    }
    if (count == 0 || !isfinite(total)) return true; // nothing to sample: BSDF sampling alone
    path_lights *pl = calloc(1, sizeof *pl);
    if (!pl) return false;
    pl->quads = malloc(count * sizeof *pl->quads);
    pl->cdf = malloc(count * sizeof *pl->cdf);
    pl->select_pdf = calloc(s->quad_count, sizeof *pl->select_pdf);
    s->path_lights = pl;
    if (!pl->quads || !pl->cdf || !pl->select_pdf) {
        path_release(s);
        return false;
    }
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < s->quad_count; i++) {
        double p = quad_light_power(s, &s->quads[i]);
        if (!(p > 0.0)) continue;
        sum += p;
        size_t k = pl->count++;
        pl->quads[k] = (uint32_t)i;
        pl->cdf[k] = pl->count == count ? 1.0f : (float)(sum / total);
        // The probability is what sampling actually gives (the cdf step), so both strategies agree on it.
        pl->select_pdf[i] = pl->cdf[k] - prev;
        prev = pl->cdf[k];
    }
    pl->quad_count = s->quad_count;
    return true;
}

// Power heuristic weight (beta = 2) of a strategy of density a against one of density b, a > 0: a^2 /
// (a^2 + b^2), in a form that neither overflows nor divides zero by zero.
static float mis_weight(float a, float b) {
    float q = b / a;
    return 1.0f / (1.0f + q * q);
}

// Probability density, per unit solid angle, with which next-event estimation would have chosen the point
// where a ray of unit direction d hit an emissive quad at distance t; 0 when it is not an indexed light.
static float quad_light_pdf(const glint_scene *s, const path_lights *pl, const surface *sf, vec3 d, float t) {
    if (sf->kind != HIT_QUAD || sf->instance != HIT_NO_INSTANCE || sf->prim >= pl->quad_count) return 0.0f;
    float select = pl->select_pdf[sf->prim];
    if (!(select > 0.0f)) return 0.0f;
    const quad *q = &s->quads[sf->prim];
    float cos_l = fabsf(v3_dot(d, q->normal));
    if (!(cos_l > 0.0f)) return 0.0f;
    return select * t * t / (cos_l * q->area);
}

// Next-event estimation towards the emissive quads at a diffuse surface point: a light chosen by power, a
// uniform point on it and a shadow ray, weighted against BSDF sampling by the power heuristic. Returns
// Le cos / (pi pdf) times the weight; the caller multiplies by the albedo and the path's throughput.
// in_side is d.ng for the arriving ray d: light below the geometric surface does not count (the BSDF
// sampling does not continue there either).
static vec3 sample_quad_light(const glint_scene *s, const path_lights *pl, const surface *sf, const spawn_point *sp,
                              float in_side, rng *r, thread_stats *ts) {
    float xi = rng_float(r), a = rng_float(r), b = rng_float(r);
    size_t lo = 0, hi = pl->count - 1; // the first light whose cdf exceeds xi
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (xi < pl->cdf[mid]) hi = mid;
        else lo = mid + 1;
    }
    uint32_t qi = pl->quads[lo];
    const quad *q = &s->quads[qi];
    const material *lm = &s->materials[q->material];
    vec3 x = v3_add(q->q, v3_add(v3_scale(q->u, a), v3_scale(q->v, b)));
    vec3 wi = v3_sub(x, sp->p);
    float d2 = v3_len2(wi);
    if (!(d2 > 0.0f) || !isfinite(d2)) return v3s(0.0f);
    float dist = sqrtf(d2);
    wi = v3_scale(wi, 1.0f / dist);
    float cos_l = -v3_dot(wi, q->normal); // > 0: the point sees the light's front (u x v) side
    if (lm->two_sided) cos_l = fabsf(cos_l);
    float cos_s = v3_dot(sf->n, wi);
    if (!(cos_l > 0.0f) || !(cos_s > 0.0f) || v3_dot(wi, sf->ng) * in_side > 0.0f) return v3s(0.0f);
    float pdf_light = pl->select_pdf[qi] * d2 / (cos_l * q->area);
    if (!(pdf_light > 0.0f) || !isfinite(pdf_light)) return v3s(0.0f);
    // Stop short of the light by a relative margin (pbrt's shadow epsilon) so that it does not occlude itself.
    ray shadow = spawn_ray(sp, wi, 0.0f, dist * (1.0f - 1e-4f));
    ts->shadow_rays++;
    if (accel_occluded(s->accel, &shadow)) return v3s(0.0f);
    vec3 le = mat_emitted(lm, s->textures, true, a, b, x);
    float w = mis_weight(pdf_light, cos_s * inv_pi);
    return v3_scale(le, cos_s * inv_pi * w / pdf_light);
}

// Direct light from the scene's point and directional lights at a diffuse surface point: BRDF (weight / pi)
// times irradiance, unoccluded. Point lights fall off with the inverse square of the distance; a
// directional light's intensity is the irradiance it gives a surface facing it. Ambient lights have no
// place in a path tracer (the background is the ambient light) and are ignored.
static vec3 direct_light(const glint_scene *s, const spawn_point *sp, vec3 n, vec3 weight, thread_stats *ts) {
    vec3 sum = v3s(0.0f);
    for (size_t i = 0; i < s->light_count; i++) {
        const light *l = &s->lights[i];
        vec3 wl;
        float dist, falloff;
        if (l->kind == LIGHT_POINT) {
            vec3 to = v3_sub(l->position, sp->p);
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
        ray shadow = spawn_ray(sp, wl, 0.0f, dist * (1.0f - 0x1p-20f));
        ts->shadow_rays++;
        if (accel_occluded(s->accel, &shadow)) continue;
        sum = v3_add(sum, v3_scale(l->intensity, cos_l * falloff));
    }
    return v3_scale(v3_mul(sum, weight), inv_pi);
}

vec3 path_sample(const glint_scene *s, int x, int y, uint32_t sample, rng *r, thread_stats *ts) {
    (void)sample;
    ray primary = integrator_camera_ray(s, x, y, r);
    return path_trace(s, primary, r, ts);
}

vec3 path_trace(const glint_scene *s, ray cur, rng *r, thread_stats *ts) {
    vec3 radiance = v3s(0.0f), throughput = v3s(1.0f);
    bool has_lights = s->light_count > 0;
    const path_lights *pl = s->settings.no_light_sampling ? NULL : s->path_lights;
    bool light_sampled = false; // the last vertex sampled the quad lights: a hit on one is weighted
    float bsdf_pdf = 0.0f;      // solid-angle density of the direction the last vertex sampled
    bool lean = !has_lights && !pl;
    for (int depth = 0; depth < s->settings.max_depth; depth++) {
        hit h;
        ts->rays++;
        if (!accel_intersect(s->accel, &cur, &h)) {
            radiance = v3_add(radiance, v3_mul(throughput, scene_background(&s->settings, cur.d)));
            break;
        }
        // A world sphere of an untextured material that does not emit, with no light to sample (the book's
        // scenes): exactly what the general code below computes for it, without the surface record, texture
        // lookups, emission, shading normals and light sampling, which cost as much as the bounce itself.
        if (lean && h.kind == HIT_SPHERE && h.instance == HIT_NO_INSTANCE) {
            const sphere *sp = &s->spheres[h.prim];
            const material *m = &s->materials[sp->material];
            if (m->kind != MAT_DIFFUSE_LIGHT && m->albedo_texture < 0) {
                vec3 p, n;
                sphere_hit_frame(sp, &cur, h.t, &p, &n);
                bool front = v3_dot(cur.d, n) < 0.0f;
                if (!front) n = v3_neg(n);
                scatter_event ev;
                if (!mat_scatter(m, m->albedo, cur.d, n, front, r, &ev)) break;
                throughput = v3_mul(throughput, ev.weight);
                if (!(throughput.x > 0.0f || throughput.y > 0.0f || throughput.z > 0.0f)) break;
                spawn_point spt = spawn_point_sphere(p, n, sp->radius);
                cur = spawn_ray(&spt, ev.dir, 0.0f, INFINITY);
                continue;
            }
        }
        surface sf = surface_at(s, &cur, &h);
        const material *m = &s->materials[sf.material];
        if (m->kind == MAT_DIFFUSE_LIGHT) {
            vec3 le = mat_emitted(m, s->textures, sf.front, sf.u, sf.v, sf.p);
            if (light_sampled) {
                float pdf_light = quad_light_pdf(s, pl, &sf, cur.d, h.t);
                if (pdf_light > 0.0f) le = v3_scale(le, mis_weight(bsdf_pdf, pdf_light));
            }
            radiance = v3_add(radiance, v3_mul(throughput, le));
            break;
        }
        scatter_event ev;
        vec3 albedo = mat_albedo(m, s->textures, sf.u, sf.v, sf.p);
        if (!mat_scatter(m, albedo, cur.d, sf.n, sf.front, r, &ev)) break;
        spawn_point sp = spawn_point_of(s, &sf);
        float in_side = v3_dot(cur.d, sf.ng);
        light_sampled = false;
        if (ev.diffuse) {
            if (has_lights) radiance = v3_add(radiance, v3_mul(throughput, direct_light(s, &sp, sf.n, ev.weight, ts)));
            // Only where the BSDF sample is traced too, so that the two strategies cover the same paths.
            if (pl && depth + 1 < s->settings.max_depth) {
                vec3 direct = sample_quad_light(s, pl, &sf, &sp, in_side, r, ts);
                radiance = v3_add(radiance, v3_mul(throughput, v3_mul(ev.weight, direct)));
                light_sampled = true;
                bsdf_pdf = v3_dot(ev.dir, sf.n) * inv_pi;
            }
        }
        // With shading normals a sampled direction can cross the geometric surface against its event
        // (reflect through it, or refract back): the path is absorbed rather than leaking light. (Where the
        // normals agree, only rounding could do that, at grazing refraction: the path goes on as before.)
        if (sf.n.x != sf.ng.x || sf.n.y != sf.ng.y || sf.n.z != sf.ng.z) {
            float out_side = v3_dot(ev.dir, sf.ng);
            if (ev.transmitted ? in_side * out_side < 0.0f : in_side * out_side > 0.0f) break;
        }
        throughput = v3_mul(throughput, ev.weight);
        // A black throughput can gain nothing more: end the path without tracing the rest.
        if (!(throughput.x > 0.0f || throughput.y > 0.0f || throughput.z > 0.0f)) break;
        cur = spawn_ray(&sp, ev.dir, 0.0f, INFINITY);
    }
    return radiance;
}
