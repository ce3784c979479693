// nee.c — next-event estimation (nee.h): a direction towards a light, its shadow ray through the media, and the
// sample's weight against the BSDF's or the phase function's own sampling.
#include "integrator/nee.h"
#include "integrator/alpha_mask.h"
#include "light/light.h"
#include "medium/medium.h"

#include <math.h>

static const float inv_pi = 0.318309886183791f;


// The density of scattering towards unit wi, cos/pi at the diffuse surface or the phase function in a medium,
// which is also the density of the direction the path samples there (for MIS); 0 where the vertex does not
// scatter towards wi: below the shading normal, or across the geometric surface from the arriving ray (the
// BSDF sampling does not continue there either).
static inline float nee_density(const nee_vertex *vx, vec3 wi) {
    if (!vx->sf) return phase_hg(vx->g, v3_dot(vx->d, wi));
    float cos_s = v3_dot(vx->sf->n, wi);
    if (!(cos_s > 0.0f) || v3_dot(wi, vx->sf->ng) * vx->in_side > 0.0f) return 0.0f;
    return cos_s * inv_pi;
}

// At a vertex with a BSDF: f cos towards unit wi, and its BSDF sampling's density there into *pdf; zero where the
// shading and geometric normals disagree on whether wi is reflected or transmitted (the sampled paths are absorbed
// there too: path_crosses).
static inline vec3 nee_bsdf(const nee_vertex *vx, vec3 wi, float *pdf) {
    float cos_s = v3_dot(vx->b->n, wi);
    bool reflected = v3_dot(wi, vx->sf->ng) * vx->in_side < 0.0f;
    *pdf = 0.0f;
    if (cos_s == 0.0f || (cos_s > 0.0f) != reflected) return v3s(0.0f);
    *pdf = bsdf_pdf(vx->b, vx->wo, wi);
    return v3_scale(bsdf_eval(vx->b, vx->wo, wi), fabsf(cos_s));
}

// How the vertex scatters towards unit wi: the density of its own sampling there (*f, for MIS) and, at a BSDF
// vertex, f cos (*fc); false when it does not scatter there.
static inline bool nee_response(const nee_vertex *vx, vec3 wi, float *f, vec3 *fc) {
    if (vx->b) {
        *fc = nee_bsdf(vx, wi, f);
        return v3_max_comp(*fc) > 0.0f;
    }
    *fc = v3s(0.0f);
    *f = nee_density(vx, wi);
    return *f > 0.0f;
}

// A light sample's contribution: Le tr f / pdf_light, weighted against the vertex's own sampling (density f) by
// the power heuristic; f cos at a BSDF vertex (fc), the density itself at diffuse surfaces and in media (whose
// callers multiply by the albedo or the phase weight).
static inline vec3 nee_contribution(const nee_vertex *vx, vec3 le, vec3 tr, float f, vec3 fc, float pdf_light) {
    if (vx->b) {
        float w = vx->light_only ? 1.0f : nee_mis_weight(pdf_light, f);
        return v3_mul(v3_mul(le, tr), v3_scale(fc, w / pdf_light));
    }
    float w = nee_mis_weight(pdf_light, f);
    return v3_scale(v3_mul(le, tr), f * w / pdf_light);
}

// Whether shadow ray r from vertex vx gets past every surface (glass included); *tr is then the transmittance of
// the media it crosses (1 in a scene without media).
static inline bool shadow_unblocked(const integrator *it, const nee_vertex *vx, const ray *r, vec3 *tr) {
    if (it->alpha_masks ? alpha_occluded(it->accel, it->scene, r) : accel_occluded_hinted(it->accel, r, vx->occluder))
        return false;
    const glint_scene *s = it->scene;
    *tr = s->medium_count ? medium_transmittance(s->media, s->medium_count, r->o, r->d, r->tmin, r->tmax) : v3s(1.0f);
    return true;
}

// Next-event estimation towards emissive sphere `index`, chosen with probability `select`: a direction in the cone
// the sphere subtends (a, b uniform), its emission where that direction meets the sphere, a shadow ray, and the
// power-heuristic weight against BSDF sampling; the same contract as nee_area_lights.
static vec3 sample_sphere_light(const integrator *it, float select, uint32_t index, const nee_vertex *vx,
                                const spawn_point *sp, float a, float b, thread_stats *ts) {
    const glint_scene *s = it->scene;
    const sphere *sph = &s->spheres[index];
    vec3 wi;
    float dist, cone_pdf;
    if (!light_sphere_sample(sph, sp->p, a, b, &wi, &dist, &cone_pdf)) return v3s(0.0f);
    float f;
    vec3 fc;
    if (!nee_response(vx, wi, &f, &fc)) return v3s(0.0f);
    float pdf_light = select * cone_pdf;
    if (!(pdf_light > 0.0f) || !isfinite(pdf_light)) return v3s(0.0f);
    // The side and texture coordinates a ray along wi sees there, as surface_at gives them.
    vec3 x = v3_fma(sp->p, wi, dist), q = v3_sub(x, sph->center);
    float len = sqrtf(v3_len2(q));
    if (!(len > 0.0f)) return v3s(0.0f);
    vec3 outward = v3_scale(q, copysignf(1.0f / len, sph->radius));
    const material *m = &s->materials[sph->material];
    float u = 0.0f, v = 0.0f;
    if (m->emission_texture >= 0 || m->alpha_texture >= 0)
        sphere_uv(sph->radius < 0.0f ? v3_neg(outward) : outward, &u, &v);
    if (alpha_cut_at(m, s->textures, u, v)) return v3s(0.0f); // a cut part emits nothing, as paths see it
    vec3 le = mat_emitted(m, s->textures, v3_dot(wi, outward) < 0.0f, u, v, x);
    if (!(le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) return v3s(0.0f);
    // Stop short of the light by a relative margin (pbrt's shadow epsilon) so that it does not occlude itself.
    ray shadow = spawn_ray(sp, wi, 0.0f, dist * (1.0f - 1e-4f));
    ts->shadow_rays++;
    vec3 tr;
    if (!shadow_unblocked(it, vx, &shadow, &tr)) return v3s(0.0f);
    return nee_contribution(vx, le, tr, f, fc, pdf_light);
}

// Next-event estimation towards the emissive quads and triangles at a diffuse surface point or a point in a
// medium: a light chosen by power, a uniform point on it and a shadow ray, weighted against BSDF (phase)
// sampling by the power heuristic. Returns Le f / pdf times the weight and the transmittance, f the vertex's
// nee_density (cos/pi at a surface); the caller multiplies by the albedo and the path's throughput.
vec3 nee_area_lights(const integrator *it, const light_sampler *pl, const nee_vertex *vx, const spawn_point *sp,
                     rng *r, thread_stats *ts) {
    const glint_scene *s = it->scene;
    rng_decision(r, RNG_DIM_LIGHT);
    // One light needs no choice: its number is not drawn (the point on it keeps its pair of dimensions).
    float xi = pl->count > 1 || pl->tree.node_count ? rng_float(r) : 0.0f, a, b, select;
    rng_float2(r, &a, &b);
    size_t chosen = light_sampler_choose(pl, sp->p, xi, &select);
    if (chosen == SIZE_MAX) return v3s(0.0f); // no light can reach the point
    light_ref ref = pl->lights[chosen];
    if (ref.kind == LIGHT_REF_SPHERE) return sample_sphere_light(it, select, ref.index, vx, sp, a, b, ts);
    vec3 x, n;
    float area;
    const tri_light *tl = NULL;
    float b1 = 0.0f, b2 = 0.0f;
    const quad *q = NULL;
    if (ref.kind == LIGHT_REF_TRIANGLE) {
        tl = &pl->tris[ref.index];
        // Uniform on the triangle: barycentrics (1 - sqrt a, sqrt a (1 - b), sqrt a b).
        float sa = sqrtf(a);
        b1 = sa * (1.0f - b);
        b2 = sa * b;
        x = v3_add(tl->p0, v3_add(v3_scale(tl->e1, b1), v3_scale(tl->e2, b2)));
        n = tl->n;
        area = tl->area;
    } else {
        q = &s->quads[ref.index];
        x = v3_add(q->q, v3_add(v3_scale(q->u, a), v3_scale(q->v, b)));
        n = q->normal;
        area = q->area;
    }
    vec3 wi = v3_sub(x, sp->p);
    float d2 = v3_len2(wi);
    if (!(d2 > 0.0f) || !isfinite(d2)) return v3s(0.0f);
    float dist = sqrtf(d2);
    wi = v3_scale(wi, 1.0f / dist);
    float cos_l = -v3_dot(wi, n); // > 0: the point sees the quad's front (u x v) side
    vec3 le;
    if (q) {
        const material *lm = &s->materials[q->material];
        if (lm->two_sided) cos_l = fabsf(cos_l);
        le = v3s(0.0f); // looked up once the point is known to be lit
    } else {
        cos_l = fabsf(cos_l);
        // The emitting side of a triangle is its shading record's: zero emission from the other side.
        le = light_sampler_tri_emitted(s, tl, b1, b2, x, wi);
        if (!(le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) return v3s(0.0f);
    }
    float f;
    vec3 fc;
    bool scatters = nee_response(vx, wi, &f, &fc);
    if (!(cos_l > 0.0f) || !scatters) return v3s(0.0f);
    float pdf_light = select * d2 / (cos_l * area);
    if (!(pdf_light > 0.0f) || !isfinite(pdf_light)) return v3s(0.0f);
    // Stop short of the light by a relative margin (pbrt's shadow epsilon) so that it does not occlude itself.
    ray shadow = spawn_ray(sp, wi, 0.0f, dist * (1.0f - 1e-4f));
    ts->shadow_rays++;
    vec3 tr;
    if (!shadow_unblocked(it, vx, &shadow, &tr)) return v3s(0.0f);
    if (q) le = alpha_cut_at(&s->materials[q->material], s->textures, a, b) // a cut part emits nothing
                    ? v3s(0.0f) : mat_emitted(&s->materials[q->material], s->textures, true, a, b, x);
    return nee_contribution(vx, le, tr, f, fc, pdf_light);
}

// Next-event estimation towards the environment map: a direction drawn in proportion to the map's brightness
// (envmap_sample), a shadow ray to infinity, and the power-heuristic weight against BSDF sampling, whose rays
// that escape are weighted in turn (the path tracer's escaping rays); the same contract as nee_area_lights.
vec3 nee_environment(const integrator *it, const envmap_sampler *es, const nee_vertex *vx, const spawn_point *sp,
                     rng *r, thread_stats *ts) {
    rng_decision(r, RNG_DIM_ENVIRONMENT);
    float a, b;
    rng_float2(r, &a, &b);
    vec3 wi, le;
    float pdf;
    if (!envmap_sample(es, &it->scene->environment, a, b, &wi, &pdf, &le)) return v3s(0.0f);
    float f;
    vec3 fc;
    if (!nee_response(vx, wi, &f, &fc)) return v3s(0.0f);
    if (!(le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) return v3s(0.0f);
    ray shadow = spawn_ray(sp, wi, 0.0f, INFINITY);
    ts->shadow_rays++;
    vec3 tr;
    if (!shadow_unblocked(it, vx, &shadow, &tr)) return v3s(0.0f);
    return nee_contribution(vx, le, tr, f, fc, pdf);
}

// Direct light from the scene's point and directional lights at a diffuse surface point (BRDF weight / pi
// times irradiance) or a point in a medium (weight times phase function times irradiance), unoccluded and
// through the media's transmittance. Point lights fall off with the inverse square of the distance; a
// directional light's intensity is the irradiance it gives a surface facing it; a spot light is a point light
// times its cone's falloff (light_spot_falloff). Ambient lights have no
// place in a path tracer (the background is the ambient light) and are ignored.
vec3 nee_point_lights(const integrator *it, const spawn_point *sp, const nee_vertex *vx, vec3 weight,
                      thread_stats *ts) {
    const glint_scene *s = it->scene;
    vec3 sum = v3s(0.0f);
    for (size_t i = 0; i < s->light_count; i++) {
        const light *l = &s->lights[i];
        vec3 wl;
        float dist, falloff;
        if (l->kind == LIGHT_POINT || l->kind == LIGHT_SPOT) {
            vec3 to = v3_sub(l->position, sp->p);
            float d2 = v3_len2(to);
            if (!(d2 > 0.0f)) continue;
            dist = sqrtf(d2);
            wl = v3_scale(to, 1.0f / dist);
            falloff = 1.0f / d2;
            if (l->kind == LIGHT_SPOT && !((falloff *= light_spot_falloff(l, wl)) > 0.0f)) continue;
        } else if (l->kind == LIGHT_DIRECTIONAL) {
            if (!(v3_len2(l->direction) > 0.0f)) continue;
            wl = v3_unit(l->direction);
            dist = INFINITY;
            falloff = 1.0f;
        } else {
            continue;
        }
        float cos_l, unused;
        vec3 fc = v3s(0.0f);
        if (vx->b) { // a BSDF vertex: f cos in place of the cosine
            fc = nee_bsdf(vx, wl, &unused);
            cos_l = v3_max_comp(fc);
        } else {
            cos_l = vx->sf ? v3_dot(vx->sf->n, wl) : phase_hg(vx->g, v3_dot(vx->d, wl));
        }
        if (!(cos_l > 0.0f)) continue;
        // Stop just short of a point light: whatever lies beyond it casts no shadow.
        ray shadow = spawn_ray(sp, wl, 0.0f, dist * (1.0f - 0x1p-20f));
        ts->shadow_rays++;
        vec3 tr;
        if (!shadow_unblocked(it, vx, &shadow, &tr)) continue;
        if (vx->b) sum = v3_add(sum, v3_mul(v3_mul(v3_scale(l->intensity, falloff), fc), tr));
        else sum = v3_add(sum, v3_mul(v3_scale(l->intensity, cos_l * falloff), tr));
    }
    if (vx->b) return v3_mul(sum, weight);
    return vx->sf ? v3_scale(v3_mul(sum, weight), inv_pi) : v3_mul(sum, weight);
}

