// path.c — the path tracer of "Ray Tracing in One Weekend", iterative: a path traces at most max_depth
// rays, each surface scatters it by its material (material/scatter.h), and escaping rays see the
// background. At diffuse surfaces, point and directional lights are added by next-event estimation, and so
// are emissive quads, mesh triangles and spheres, combined with the BSDF samples that hit them by multiple
// importance sampling. Participating media (medium/medium.h) scatter paths inside them, and the same lights
// are sampled there with the phase function, their shadow rays carrying the media's transmittance.
#include "integrator/integrator.h"
#include "integrator/light_sampler.h"
#include "integrator/spawn.h"
#include "integrator/surface.h"
#include "material/scatter.h"

#include "camera/camera_batch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const float inv_pi = 0.318309886183791f;

/// The path tracer: the common integrator state and its light sampler (pbrt's PathIntegrator owns its own).
typedef struct path_integrator {
    integrator base;
    light_sampler lights;
    const light_sampler *sampled; ///< &lights when next-event estimation samples the emissive surfaces, else NULL
    envmap_sampler environment;
    const envmap_sampler *env_sampled; ///< &environment when next-event estimation samples the envmap, else NULL
} path_integrator;

// Power heuristic weight (beta = 2) of a strategy of density a against one of density b, a > 0: a^2 /
// (a^2 + b^2), in a form that neither overflows nor divides zero by zero.
static float mis_weight(float a, float b) {
    float q = b / a;
    return 1.0f / (1.0f + q * q);
}

/// What next-event estimation needs of the point it lights: a diffuse surface (sf: its normals; in_side = d.ng
/// for the arriving ray d) or a point in a medium (sf NULL: the arriving ray's unit direction d and the phase
/// function's g).
typedef struct nee_vertex {
    const surface *sf;
    float in_side;
    vec3 d;
    float g;
} nee_vertex;

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

// Whether shadow ray r gets past every surface (glass included); *tr is then the transmittance of the media it
// crosses (1 in a scene without media).
static inline bool shadow_unblocked(const integrator *it, const ray *r, vec3 *tr) {
    if (accel_occluded(it->accel, r)) return false;
    const glint_scene *s = it->scene;
    *tr = s->medium_count ? medium_transmittance(s->media, s->medium_count, r->o, r->d, r->tmin, r->tmax) : v3s(1.0f);
    return true;
}

// Next-event estimation towards emissive sphere `index`: a direction in the cone the sphere subtends (a, b
// uniform), its emission where that direction meets the sphere, a shadow ray, and the power-heuristic weight
// against BSDF sampling; the same contract as sample_light.
static vec3 sample_sphere_light(const integrator *it, const light_sampler *pl, uint32_t index, const nee_vertex *vx,
                                const spawn_point *sp, float a, float b, thread_stats *ts) {
    const glint_scene *s = it->scene;
    const sphere *sph = &s->spheres[index];
    vec3 wi;
    float dist, cone_pdf;
    if (!light_sphere_sample(sph, sp->p, a, b, &wi, &dist, &cone_pdf)) return v3s(0.0f);
    float f = nee_density(vx, wi);
    if (!(f > 0.0f)) return v3s(0.0f);
    float pdf_light = pl->sphere_select_pdf[index] * cone_pdf;
    if (!(pdf_light > 0.0f) || !isfinite(pdf_light)) return v3s(0.0f);
    // The side and texture coordinates a ray along wi sees there, as surface_at gives them.
    vec3 x = v3_fma(sp->p, wi, dist), q = v3_sub(x, sph->center);
    float len = sqrtf(v3_len2(q));
    if (!(len > 0.0f)) return v3s(0.0f);
    vec3 outward = v3_scale(q, copysignf(1.0f / len, sph->radius));
    const material *m = &s->materials[sph->material];
    float u = 0.0f, v = 0.0f;
    if (m->emission_texture >= 0) sphere_uv(sph->radius < 0.0f ? v3_neg(outward) : outward, &u, &v);
    vec3 le = mat_emitted(m, s->textures, v3_dot(wi, outward) < 0.0f, u, v, x);
    if (!(le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) return v3s(0.0f);
    // Stop short of the light by a relative margin (pbrt's shadow epsilon) so that it does not occlude itself.
    ray shadow = spawn_ray(sp, wi, 0.0f, dist * (1.0f - 1e-4f));
    ts->shadow_rays++;
    vec3 tr;
    if (!shadow_unblocked(it, &shadow, &tr)) return v3s(0.0f);
    float w = mis_weight(pdf_light, f);
    return v3_scale(v3_mul(le, tr), f * w / pdf_light);
}

// Next-event estimation towards the emissive quads and triangles at a diffuse surface point or a point in a
// medium: a light chosen by power, a uniform point on it and a shadow ray, weighted against BSDF (phase)
// sampling by the power heuristic. Returns Le f / pdf times the weight and the transmittance, f the vertex's
// nee_density (cos/pi at a surface); the caller multiplies by the albedo and the path's throughput.
static vec3 sample_light(const integrator *it, const light_sampler *pl, const nee_vertex *vx, const spawn_point *sp,
                         rng *r, thread_stats *ts) {
    const glint_scene *s = it->scene;
    float xi = rng_float(r), a = rng_float(r), b = rng_float(r);
    size_t lo = 0, hi = pl->count - 1; // the first light whose cdf exceeds xi
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (xi < pl->cdf[mid]) hi = mid;
        else lo = mid + 1;
    }
    float select = pl->cdf[lo] - (lo ? pl->cdf[lo - 1] : 0.0f); // as light_sampler_build recorded it
    light_ref ref = pl->lights[lo];
    if (ref.kind == LIGHT_REF_SPHERE) return sample_sphere_light(it, pl, ref.index, vx, sp, a, b, ts);
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
    float f = nee_density(vx, wi);
    if (!(cos_l > 0.0f) || !(f > 0.0f)) return v3s(0.0f);
    float pdf_light = (q ? pl->select_pdf[ref.index] : select) * d2 / (cos_l * area);
    if (!(pdf_light > 0.0f) || !isfinite(pdf_light)) return v3s(0.0f);
    // Stop short of the light by a relative margin (pbrt's shadow epsilon) so that it does not occlude itself.
    ray shadow = spawn_ray(sp, wi, 0.0f, dist * (1.0f - 1e-4f));
    ts->shadow_rays++;
    vec3 tr;
    if (!shadow_unblocked(it, &shadow, &tr)) return v3s(0.0f);
    if (q) le = mat_emitted(&s->materials[q->material], s->textures, true, a, b, x);
    float w = mis_weight(pdf_light, f);
    return v3_scale(v3_mul(le, tr), f * w / pdf_light);
}

// Next-event estimation towards the environment map: a direction drawn in proportion to the map's brightness
// (envmap_sample), a shadow ray to infinity, and the power-heuristic weight against BSDF sampling, whose rays
// that escape are weighted in turn (path_trace); the same contract as sample_light.
static vec3 sample_environment(const integrator *it, const envmap_sampler *es, const nee_vertex *vx,
                               const spawn_point *sp, rng *r, thread_stats *ts) {
    float a = rng_float(r), b = rng_float(r);
    vec3 wi, le;
    float pdf;
    if (!envmap_sample(es, &it->scene->environment, a, b, &wi, &pdf, &le)) return v3s(0.0f);
    float f = nee_density(vx, wi);
    if (!(f > 0.0f)) return v3s(0.0f);
    if (!(le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) return v3s(0.0f);
    ray shadow = spawn_ray(sp, wi, 0.0f, INFINITY);
    ts->shadow_rays++;
    vec3 tr;
    if (!shadow_unblocked(it, &shadow, &tr)) return v3s(0.0f);
    float w = mis_weight(pdf, f);
    return v3_scale(v3_mul(le, tr), f * w / pdf);
}

// Direct light from the scene's point and directional lights at a diffuse surface point (BRDF weight / pi
// times irradiance) or a point in a medium (weight times phase function times irradiance), unoccluded and
// through the media's transmittance. Point lights fall off with the inverse square of the distance; a
// directional light's intensity is the irradiance it gives a surface facing it. Ambient lights have no
// place in a path tracer (the background is the ambient light) and are ignored.
static vec3 direct_light(const integrator *it, const spawn_point *sp, const nee_vertex *vx, vec3 weight,
                         thread_stats *ts) {
    const glint_scene *s = it->scene;
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
        float cos_l = vx->sf ? v3_dot(vx->sf->n, wl) : phase_hg(vx->g, v3_dot(vx->d, wl));
        if (!(cos_l > 0.0f)) continue;
        // Stop just short of a point light: whatever lies beyond it casts no shadow.
        ray shadow = spawn_ray(sp, wl, 0.0f, dist * (1.0f - 0x1p-20f));
        ts->shadow_rays++;
        vec3 tr;
        if (!shadow_unblocked(it, &shadow, &tr)) continue;
        sum = v3_add(sum, v3_mul(v3_scale(l->intensity, cos_l * falloff), tr));
    }
    return vx->sf ? v3_scale(v3_mul(sum, weight), inv_pi) : v3_mul(sum, weight);
}

// Book 3's mixture density for a diffuse bounce in a scene with "importance" spheres: half the directions
// from the cosine lobe (the one mat_scatter drew), half towards one of those spheres (uniform in the cone it
// subtends). The weight becomes BRDF x cos / mixture density, and the mixture density, returned, is what MIS
// weighs a hit on a light with. A direction below the surface ends the path (weight 0).
static float aim_diffuse(const glint_scene *s, vec3 p, vec3 n, rng *r, scatter_event *ev) {
    size_t count = s->importance_sphere_count;
    if (rng_float(r) < 0.5f) {
        size_t i = (size_t)(rng_float(r) * (float)count);
        float a = rng_float(r), b = rng_float(r), dist, pdf;
        vec3 wi;
        if (light_sphere_sample(&s->spheres[s->importance_spheres[i < count ? i : count - 1]], p, a, b, &wi, &dist, &pdf))
            ev->dir = wi;
    }
    float cos_t = v3_dot(ev->dir, n), pdf = 0.5f * fmaxf(cos_t, 0.0f) * inv_pi;
    for (size_t i = 0; i < count; i++)
        pdf += 0.5f / (float)count * light_sphere_pdf_towards(&s->spheres[s->importance_spheres[i]], p, ev->dir);
    if (!(cos_t > 0.0f) || !(pdf > 0.0f)) {
        ev->weight = v3s(0.0f);
        return 0.0f;
    }
    ev->weight = v3_scale(ev->weight, cos_t * inv_pi / pdf);
    return pdf;
}

// Whether m scatters only into one direction (a perfect mirror, glass): the AOVs look past it.
static inline bool path_aov_passes(const material *m) {
    return m->kind == MAT_DIELECTRIC || (m->kind == MAT_METAL && m->fuzz == 0.0f);
}

// The AOVs of a surface vertex of a path that has so far bounced only off perfect mirrors and glass (OIDN's
// advice: follow perfect specular paths and record the first diffuse or glossy surface): the albedo seen
// through those bounces (throughput), and the normal. True while they stay pending: a mirror or glass records
// itself in case the path ends there, and the next vertex overwrites it.
static inline bool path_aov_surface(film_aov_sample *aov, vec3 throughput, vec3 albedo, vec3 n, const material *m) {
    aov->albedo = integrator_aov_albedo(v3_mul(throughput, albedo));
    aov->normal = n;
    return path_aov_passes(m);
}

/// Where a path stands between two rays, but for the ray itself and the media it is in (kept apart: their
/// addresses are passed on, which would keep the rest of the state out of registers): what it has gathered and
/// what its last vertex did.
typedef struct path_state {
    vec3 radiance, throughput;
    float bsdf_pdf;           ///< solid-angle density of the direction the last vertex sampled
    int depth;                ///< rays traced so far
    bool light_sampled;       ///< the last vertex sampled the area lights: a hit on one is weighted
    bool env_sampled;         ///< the last vertex sampled the environment: an escaping ray is weighted
    bool unit;                ///< cur.d has unit length (not so camera rays and the lean bounce's Lambertian ones)
    bool aov_pending;         ///< the AOVs wait for the path's first diffuse or glossy vertex
} path_state;

// A path that has traced nothing yet.
static inline path_state path_start(film_aov_sample *aov) {
    path_state ps = {.radiance = v3s(0.0f), .throughput = v3s(1.0f), .aov_pending = aov != NULL};
    if (aov) {
        aov->albedo = aov->normal = v3s(0.0f);
        aov->depth = INFINITY;
    }
    return ps;
}

// Whether a path's vertices need none of the lights, media or importance sampling (the book's scenes).
static inline bool path_lean(const path_integrator *pi) {
    const glint_scene *s = pi->base.scene;
    return !s->light_count && !pi->sampled && !pi->env_sampled && !s->medium_count && !s->importance_sphere_count;
}

/// What the vertices of a render's paths need to know of the scene and the integrator, looked up once per path
/// (not at every vertex). `lean`: none of the lights, media or importance sampling (path_lean).
typedef struct path_setup {
    bool has_lights;
    const light_sampler *pl;
    const envmap_sampler *es;
    size_t media; ///< none: the vertex does no work for media but this one test
    bool lean;
} path_setup;

// The setup of pi's paths; known_lean (a constant after inlining, true only where path_lean holds) leaves the
// code for lights and media out of the vertices that use it.
static inline path_setup path_setup_of(const path_integrator *pi, bool known_lean) {
    const glint_scene *s = pi->base.scene;
    if (known_lean) return (path_setup){false, NULL, NULL, 0, true};
    return (path_setup){s->light_count > 0, pi->sampled, pi->env_sampled, s->medium_count, path_lean(pi)};
}

// Makes the direction of the ray *cur that ended at hit *h a unit vector: the same ray, t in its units.
static inline void path_unit_direction(path_state *ps, ray *cur, hit *h) {
    float len = v3_len(cur->d);
    cur->d = v3_scale(cur->d, 1.0f / len);
    h->t *= len;
    ps->unit = true;
}

// With shading normals a sampled direction `dir` can cross the geometric surface sf against its event (reflect
// through it, or refract back): the path is then absorbed rather than leaking light. (Where the normals agree,
// only rounding could do that, at grazing refraction: the path goes on as before.) `in_side`: d.ng for the
// arriving ray d.
static inline bool path_crosses(const surface *sf, float in_side, vec3 dir, bool transmitted) {
    if (sf->n.x == sf->ng.x && sf->n.y == sf->ng.y && sf->n.z == sf->ng.z) return false;
    float out_side = v3_dot(dir, sf->ng);
    return transmitted ? in_side * out_side < 0.0f : in_side * out_side > 0.0f;
}

// The path goes on from sp along dir, its throughput times `weight`; false (the path ends) when that is black,
// as nothing more can be gained.
static inline bool path_continue(path_state *ps, ray *cur, const spawn_point *sp, vec3 weight, vec3 dir) {
    ps->throughput = v3_mul(ps->throughput, weight);
    if (!(ps->throughput.x > 0.0f || ps->throughput.y > 0.0f || ps->throughput.z > 0.0f)) return false;
    *cur = spawn_ray(sp, dir, 0.0f, INFINITY);
    return true;
}

// What the path does where its ray *cur ends, at hit *h (found; by address, as the query wrote it: a copy would
// load it whole, which waits for the query's stores to retire) or in the background, at depth ps->depth:
// gathers light into ps->radiance and makes the next ray. False when the path ends there.
static inline __attribute__((always_inline)) bool path_vertex(const path_integrator *pi, path_setup setup,
                                                             path_state *ps, ray *cur, medium_path *mpath, bool found,
                                                             hit *h, rng *r, thread_stats *ts, film_aov_sample *aov) {
    const integrator *it = &pi->base;
    const glint_scene *s = it->scene;
    bool has_lights = setup.has_lights, lean = setup.lean;
    const light_sampler *pl = setup.pl;
    const envmap_sampler *es = setup.es;
    size_t media = setup.media;
    int depth = ps->depth;
    if (media) {
        if (!ps->unit) { // distances in the media are lengths: a unit direction, t in its units
            float len = v3_len(cur->d);
            cur->d = v3_scale(cur->d, 1.0f / len);
            if (found) h->t *= len;
            ps->unit = true;
        }
        // The ray's free flight through the media up to the surface it meets (or to infinity).
        medium_event me =
            medium_sample(s->media, media, s->textures, cur->o, cur->d, found ? h->t : INFINITY, mpath, r);
        ps->throughput = v3_mul(ps->throughput, me.weight);
        if (!(ps->throughput.x > 0.0f || ps->throughput.y > 0.0f || ps->throughput.z > 0.0f)) return false;
        if (me.scattered) {
            // It scatters in the medium: the lights are sampled as at a diffuse surface, with the phase
            // function in place of the BSDF, and the next direction is drawn from the phase function.
            float g = s->media[me.index].g;
            nee_vertex nv = {NULL, 0.0f, cur->d, g};
            spawn_point mp = {me.p, v3s(0.0f), 0.0f, cur->time}; // no surface to step off; the path's time
            bool more = depth + 1 < s->settings.max_depth;
            ps->light_sampled = ps->env_sampled = false;
            if (has_lights) ps->radiance = v3_add(ps->radiance, direct_light(it, &mp, &nv, ps->throughput, ts));
            if (pl && more) {
                ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, sample_light(it, pl, &nv, &mp, r, ts)));
                ps->light_sampled = true;
            }
            if (es && more) {
                vec3 direct = sample_environment(it, es, &nv, &mp, r, ts);
                ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, direct));
                ps->env_sampled = true;
            }
            float a = rng_float(r), b = rng_float(r);
            vec3 wi = phase_hg_sample(g, cur->d, a, b);
            ps->bsdf_pdf = phase_hg(g, v3_dot(cur->d, wi));
            *cur = (ray){me.p, wi, 0.0f, INFINITY, cur->time};
            return true;
        }
    }
    if (!found) {
        if (!ps->unit) cur->d = v3_unit(cur->d);
        vec3 bg = scene_background(s, cur->d);
        // The background seen (through mirrors and glass) is the albedo; the normal stays (0 for no surface).
        if (ps->aov_pending) aov->albedo = integrator_aov_albedo(v3_mul(ps->throughput, bg));
        if (ps->env_sampled) bg = v3_scale(bg, mis_weight(ps->bsdf_pdf, envmap_pdf(es, &s->environment, cur->d)));
        ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, bg));
        return false;
    }
    if (aov && depth == 0) aov->depth = ps->unit ? h->t : h->t * v3_len(cur->d); // camera rays may be unnormalised
    // A world sphere of an untextured material that does not emit, with no light to sample (the book's
    // scenes): exactly what the general code below computes for it, without the surface record, texture
    // lookups, emission, shading normals and light sampling, which cost as much as the bounce itself.
    if (lean && h->kind == HIT_SPHERE && h->instance == HIT_NO_INSTANCE) {
        const sphere *sp = &s->spheres[h->prim];
        const material *m = &s->materials[sp->material];
        if (m->kind != MAT_DIFFUSE_LIGHT && m->albedo_texture < 0) {
            vec3 p, n;
            sphere_hit_frame(sp, cur, h->t, &p, &n);
            bool front = v3_dot(cur->d, n) < 0.0f;
            if (!front) n = v3_neg(n);
            if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, m->albedo, n, m);
            scatter_event ev;
            if (m->kind == MAT_LAMBERTIAN) {
                // Only the direction matters to the next intersection: the normalisation (a square root
                // and a division) waits until a mirror, glass or the background needs a unit vector.
                ev.dir = mat_lambertian_sum(n, sample_sphere_uniform(r));
                ev.weight = m->albedo;
                ps->unit = false;
            } else {
                if (!ps->unit) cur->d = v3_unit(cur->d);
                ps->unit = true;
                if (!mat_scatter(m, m->albedo, cur->d, n, front, r, &ev)) return false;
            }
            ps->throughput = v3_mul(ps->throughput, ev.weight);
            if (!(ps->throughput.x > 0.0f || ps->throughput.y > 0.0f || ps->throughput.z > 0.0f)) return false;
            spawn_point spt = spawn_point_sphere(p, n, sp->radius, cur->time);
            *cur = spawn_ray(&spt, ev.dir, 0.0f, INFINITY);
            return true;
        }
    }
    // The general code below works with unit directions: the same ray, t in its units. A lean path's Lambertian
    // surface needs none (the book's n + u, as at spheres above): it waits until the material is known.
    if (!ps->unit && !lean) path_unit_direction(ps, cur, h);
    surface sf;
    bool flat = lean && surface_at_flat(s, cur, h, &sf);
    if (!flat) sf = surface_at(s, cur, h);
    const material *m = &s->materials[sf.material];
    if (flat && m->kind == MAT_LAMBERTIAN && m->albedo_texture < 0) {
        // A lean path at an untextured Lambertian quad or mesh (the floors and models of most scenes): what the
        // code below computes for it, without its general cases, which cost 5 % on the bunny.
        if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, m->albedo, sf.n, m);
        vec3 dir = mat_lambertian_sum(sf.n, sample_sphere_uniform(r));
        if (path_crosses(&sf, v3_dot(cur->d, sf.ng), dir, false)) return false;
        spawn_point sp = spawn_point_of(s, &sf);
        ps->unit = false;
        return path_continue(ps, cur, &sp, m->albedo, dir);
    }
    bool lean_diffuse = lean && m->kind == MAT_LAMBERTIAN;
    if (!ps->unit && !lean_diffuse) path_unit_direction(ps, cur, h);
    if (m->kind == MAT_DIFFUSE_LIGHT) {
        vec3 tp = surface_texture_point(s, &sf, m->emission_texture);
        vec3 le = mat_emitted(m, s->textures, sf.front, sf.u, sf.v, tp);
        if (ps->aov_pending) {
            aov->albedo = integrator_aov_albedo(v3_mul(ps->throughput, integrator_aov_emitter(le)));
            aov->normal = sf.n;
        }
        if (ps->light_sampled) {
            float pdf_light = light_sampler_pdf(pl, s, &sf, cur->o, cur->d, h->t);
            if (pdf_light > 0.0f) le = v3_scale(le, mis_weight(ps->bsdf_pdf, pdf_light));
        }
        ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, le));
        return false;
    }
    scatter_event ev;
    vec3 albedo = mat_albedo(m, s->textures, sf.u, sf.v, surface_texture_point(s, &sf, m->albedo_texture));
    if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, albedo, sf.n, m);
    if (lean_diffuse) { // mat_scatter's direction, not normalised: the next ray's direction needs no unit length
        ev = (scatter_event){mat_lambertian_sum(sf.n, sample_sphere_uniform(r)), albedo, true, false};
        ps->unit = false;
    } else if (!mat_scatter(m, albedo, cur->d, sf.n, sf.front, r, &ev)) {
        return false;
    }
    spawn_point sp = spawn_point_of(s, &sf);
    float in_side = v3_dot(cur->d, sf.ng);
    ps->light_sampled = ps->env_sampled = false;
    if (ev.diffuse) {
        float dir_pdf = s->importance_sphere_count ? aim_diffuse(s, sp.p, sf.n, r, &ev)
                                                   : v3_dot(ev.dir, sf.n) * inv_pi;
        nee_vertex nv = {&sf, in_side, cur->d, 0.0f};
        if (has_lights)
            ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, direct_light(it, &sp, &nv, ev.weight, ts)));
        // Only where the BSDF sample is traced too, so that the two strategies cover the same paths.
        if (pl && depth + 1 < s->settings.max_depth) {
            vec3 direct = sample_light(it, pl, &nv, &sp, r, ts);
            ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, v3_mul(ev.weight, direct)));
            ps->light_sampled = true;
            ps->bsdf_pdf = dir_pdf;
        }
        if (es && depth + 1 < s->settings.max_depth) {
            vec3 direct = sample_environment(it, es, &nv, &sp, r, ts);
            ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, v3_mul(ev.weight, direct)));
            ps->env_sampled = true;
            ps->bsdf_pdf = dir_pdf;
        }
    }
    if (path_crosses(&sf, in_side, ev.dir, ev.transmitted)) return false;
    return path_continue(ps, cur, &sp, ev.weight, ev.dir);
}

// The radiance a path starting with the primary ray (origin o, direction d, all t > 0, at `time`) carries, and its AOVs
// when aov is not NULL. The ray comes by its parts, in registers: a whole ray passed by value is copied with
// wide loads that cannot be forwarded from the stores that just made it. d need not have unit length. One
// copy: the AOV tests are predictable branches on a NULL pointer (a second, specialised copy cost the sphere
// scenes 12 % through gcc's inlining budget).
static vec3 path_trace(const path_integrator *pi, vec3 o, vec3 d, float time, rng *r, thread_stats *ts,
                       film_aov_sample *aov, const hit *first, bool first_found) {
    const glint_scene *s = pi->base.scene;
    path_setup setup = path_setup_of(pi, false);
    path_state ps = path_start(aov);
    ray cur = {o, d, 0.0f, INFINITY, time};
    medium_path mpath = medium_path_start();
    for (; ps.depth < s->settings.max_depth; ps.depth++) {
        hit h;
        ts->rays++;
        bool found;
        if (first && ps.depth == 0) { // the camera ray, traced with its neighbours (accel_intersect_coherent)
            h = *first;
            found = first_found;
        } else {
            found = accel_intersect(pi->base.accel, &cur, &h);
        }
        if (!path_vertex(pi, setup, &ps, &cur, &mpath, found, &h, r, ts, aov)) break;
    }
    return ps.radiance;
}

// One sample of pixel (x, y): its camera ray, then its path (what path_render_tile does sixteen at a time).
static vec3 path_sample(const integrator *it, int x, int y, uint32_t sample, rng *r, thread_stats *ts,
                        film_aov_sample *aov) {
    (void)sample;
    ray primary = camera_sample_ray(&it->camera, x, y, r);
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    return path_trace(pi, primary.o, primary.d, primary.time, r, ts, aov, NULL, false);
}

/// The next sample of a tile pass to make a camera ray for: pixel (x, y), its rng_pixel_key, sample k.
typedef struct sample_cursor {
    int x, y, k;
    uint64_t key;
} sample_cursor;

static inline sample_cursor sample_cursor_start(const integrator *it, const tile_pass *tp) {
    const render_settings *rs = &it->scene->settings;
    return (sample_cursor){tp->x0, tp->y0, tp->k0,
                           rng_pixel_key(rs->seed, (uint64_t)tp->y0 * (uint64_t)rs->width + (uint64_t)tp->x0)};
}

// The camera rays (and generators) of the next n <= CAMERA_BATCH samples, in vector instructions
// (camera_batch.h); lanes past n repeat the first.
static inline __attribute__((always_inline)) void sample_cursor_batch(const integrator *it, const tile_pass *tp,
                                                                     sample_cursor *c, int n, camera_batch *cb) {
    const render_settings *rs = &it->scene->settings;
    for (int i = 0; i < CAMERA_BATCH; i++) {
        if (i >= n) {
            cb->x[i] = cb->x[0], cb->y[i] = cb->y[0], cb->key[i] = cb->key[0], cb->sample[i] = cb->sample[0];
            continue;
        }
        cb->x[i] = c->x, cb->y[i] = c->y, cb->key[i] = c->key, cb->sample[i] = (uint64_t)c->k;
        if (++c->k == tp->k1) {
            c->k = tp->k0;
            if (++c->x == tp->x1) {
                c->x = tp->x0;
                c->y++;
            }
            if (c->y < tp->y1) c->key = rng_pixel_key(rs->seed, (uint64_t)c->y * (uint64_t)rs->width + (uint64_t)c->x);
        }
    }
    camera_batch_make(&it->camera, it->stream, cb);
}

// Camera ray i of batch cb, open-ended.
static inline ray batch_ray(const camera_batch *cb, int i) {
    return (ray){cb->o[i], cb->d[i], 0.0f, INFINITY, cb->time[i]};
}

// One tile pass: the samples' camera rays are made CAMERA_BATCH at a time before their paths are traced one by
// one. Same samples, same order, same sums as path_sample one at a time: the same bytes.
static inline __attribute__((always_inline)) bool path_render_tile_with(const integrator *it, const tile_pass *tp,
                                                                       film_tile *ft, thread_stats *ts, bool aovs) {
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    int w = tp->x1 - tp->x0, spp = tp->k1 - tp->k0;
    int items = w * (tp->y1 - tp->y0) * spp; // item j: sample k0 + j % spp of pixel j / spp
    sample_cursor cursor = sample_cursor_start(it, tp); // runs ahead of the film tile's by up to CAMERA_BATCH items
    camera_batch cb;
    film_tile t = *ft; // a local copy whose address does not escape: its fields can live in registers
    // A tree of triangles traces each batch's camera rays (a pixel's samples, or neighbours) as one packet.
    bool coherent = accel_coherent(it->accel) && it->scene->settings.max_depth > 0;
    _Static_assert((int)CAMERA_BATCH <= (int)ACCEL_COHERENT, "a batch of camera rays fits in one packet");
    hit first[CAMERA_BATCH];
    bool first_found[CAMERA_BATCH] = {false};
    for (int j = 0; j < items; j += CAMERA_BATCH) {
        int n = items - j < CAMERA_BATCH ? items - j : CAMERA_BATCH;
        sample_cursor_batch(it, tp, &cursor, n, &cb);
        if (coherent) {
            ray rays[CAMERA_BATCH];
            for (int i = 0; i < n; i++) rays[i] = batch_ray(&cb, i);
            accel_intersect_coherent(it->accel, n, rays, first, first_found);
        }
        for (int i = 0; i < n; i++) {
            if (tile_pass_stopping(tp)) {
                film_tile_stop(&t);
                *ft = t;
                return false;
            }
            rng r = cb.r[i];
            bool more;
            if (aovs) {
                film_aov_sample a;
                vec3 c = path_trace(pi, cb.o[i], cb.d[i], cb.time[i], &r, ts, &a, coherent ? &first[i] : NULL,
                                    first_found[i]);
                more = film_tile_add_aov(&t, c, &a);
            } else {
                more = film_tile_add(&t, path_trace(pi, cb.o[i], cb.d[i], cb.time[i], &r, ts, NULL,
                                                    coherent ? &first[i] : NULL, first_found[i]));
            }
            if (!more) {
                *ft = t;
                return true;
            }
        }
    }
    *ft = t;
    return true;
}

/// Paths in flight in the stream loop, and samples started and not yet added to the film (a power of two). Many
/// more paths than one traversal takes at once (ACCEL_STREAM), and a window that a long path rarely fills: on
/// bunny1m 64 paths and a window of 256 ran 0.93 times as fast as 256 and 1,024, and those 0.98 times as fast as
/// 1,024 and 4,096; the bunny and the 278k bunny, traced one by one, run as fast with any (docs/benchmarks.md).
enum { PATH_STREAM = 1024, STREAM_WINDOW = 4096 };

/// The stream loop's paths in flight and its window of finished samples: about 330 kB, on the heap rather than on
/// the stack of a library caller's thread.
typedef struct path_stream {
    path_state ps[PATH_STREAM];
    rng gen[PATH_STREAM];
    int item[PATH_STREAM];
    ray rays[PATH_STREAM];
    medium_path mpath[PATH_STREAM];
    hit hits[PATH_STREAM];
    bool found[PATH_STREAM], has_hit[PATH_STREAM];
    film_aov_sample aov[PATH_STREAM];
    vec3 finished[STREAM_WINDOW];
    film_aov_sample finished_aov[STREAM_WINDOW];
    bool is_finished[STREAM_WINDOW];
} path_stream;

// Whether the stream loop traces its camera rays as packets (accel_intersect_coherent): in a BVH of triangles and
// quads, unless its streams are traversed together (accel_interleaves) and it has more leaf packets than the image
// has pixels. Then a pixel's sixteen rays spread over several leaves, and the stream traces them faster (bunny1m at
// 400x300, 1.3 leaves a pixel: packets 0.970; the 500k bunny, 0.6: 1.050; docs/benchmarks.md).
static bool stream_camera_packets(const integrator *it) {
    if (!accel_coherent(it->accel)) return false;
    if (!accel_interleaves(it->accel)) return true;
    accel_stats st;
    accel_get_stats(it->accel, &st);
    const render_settings *rs = &it->scene->settings;
    return st.leaves < (uint64_t)rs->width * (uint64_t)rs->height;
}

// The hits of the rays among rays[0, n) whose lanes have none yet (has_hit false), traversed together, ACCEL_STREAM
// at a time, when `together` (accel_interleaves), else one by one in place; the other lanes keep the hits they came
// with. Clears has_hit: the next round's rays are new.
static inline void stream_trace(const accel *a, bool together, int n, const ray *rays, bool *has_hit, hit *hits,
                                bool *found) {
    if (!together) {
        for (int l = 0; l < n; l++)
            if (!has_hit[l]) found[l] = accel_intersect(a, &rays[l], &hits[l]);
    } else {
        int lane[PATH_STREAM], m = 0;
        for (int l = 0; l < n; l++)
            if (!has_hit[l]) lane[m++] = l;
        for (int c = 0; c < m; c += ACCEL_STREAM) {
            int k = m - c < ACCEL_STREAM ? m - c : ACCEL_STREAM;
            if (m == n) { // no camera packets: the rays as they are, no copy
                accel_intersect_stream(a, k, rays + c, hits + c, found + c);
                continue;
            }
            ray todo[ACCEL_STREAM];
            hit th[ACCEL_STREAM];
            bool tf[ACCEL_STREAM];
            for (int j = 0; j < k; j++) todo[j] = rays[lane[c + j]];
            accel_intersect_stream(a, k, todo, th, tf);
            for (int j = 0; j < k; j++) hits[lane[c + j]] = th[j], found[lane[c + j]] = tf[j];
        }
    }
    for (int l = 0; l < n; l++) has_hit[l] = false; // the next round's rays are new
}

// A tile pass with many paths in flight (accel_streams): PATH_STREAM of them, the rays of each round traced before
// any is shaded (stream_trace; shadow rays, one at a time, stay in path_vertex), so that the corners of the hits a
// few paths ahead come from memory while one is shaded (SHADE_AHEAD), and a path that ends giving its place to the
// next sample. The samples (and their AOVs when `aovs`) are added to the film in their order, from a window of
// finished ones (sp): the same sums as path_render_tile_with, so the same bytes. `lean` (a constant): path_lean
// holds. A depth limit of at least 1.
static inline __attribute__((always_inline)) bool path_render_tile_stream_with(const integrator *it,
                                                                              const tile_pass *tp, film_tile *ft,
                                                                              thread_stats *ts, path_stream *sp,
                                                                              bool lean, bool aovs) {
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    int max_depth = it->scene->settings.max_depth;
    path_setup setup = path_setup_of(pi, lean);
    int w = tp->x1 - tp->x0, spp = tp->k1 - tp->k0;
    int items = w * (tp->y1 - tp->y0) * spp; // item j: sample k0 + j % spp of pixel j / spp
    enum { WINDOW = STREAM_WINDOW };
    enum { SHADE_AHEAD = 4 }; // paths between a hit whose corners are fetched and its shading
    vec3 *finished = sp->finished;
    film_aov_sample *finished_aov = sp->finished_aov, *aov = sp->aov;
    bool *is_finished = sp->is_finished;
    memset(is_finished, 0, sizeof sp->is_finished);
    path_state *ps = sp->ps;
    rng *gen = sp->gen;
    int *item = sp->item;
    ray *rays = sp->rays; // each path's next ray
    medium_path *mpath = sp->mpath;
    hit *hits = sp->hits;
    bool *found = sp->found, *has_hit = sp->has_hit;
    int lanes = 0, started = 0, added = 0; // paths in flight are lanes [0, lanes)
    sample_cursor cursor = sample_cursor_start(it, tp);
    camera_batch cb;
    int batch_start = 0, batch_end = 0; // cb holds items [batch_start, batch_end)
    film_tile t = *ft;
    // Each batch of camera rays traced as a packet when it is made (stream_camera_packets); a path that starts
    // from it comes with its first hit, and the stream traces the other paths' rays.
    bool packets = stream_camera_packets(it), together = accel_interleaves(it->accel);
    hit first[CAMERA_BATCH];
    bool first_found[CAMERA_BATCH];
    for (;;) {
        while (lanes < PATH_STREAM && started < items && started < added + WINDOW) {
            if (started == batch_end) {
                int n = items - started < CAMERA_BATCH ? items - started : CAMERA_BATCH;
                sample_cursor_batch(it, tp, &cursor, n, &cb);
                batch_start = started;
                batch_end = started + n;
                if (packets) {
                    ray cam[CAMERA_BATCH];
                    for (int k = 0; k < n; k++) cam[k] = batch_ray(&cb, k);
                    accel_intersect_coherent(it->accel, n, cam, first, first_found);
                }
            }
            int i = started - batch_start;
            ps[lanes] = path_start(aovs ? &aov[lanes] : NULL);
            rays[lanes] = batch_ray(&cb, i);
            mpath[lanes] = medium_path_start();
            gen[lanes] = cb.r[i];
            has_hit[lanes] = packets;
            if (packets) hits[lanes] = first[i], found[lanes] = first_found[i];
            item[lanes++] = started++;
        }
        if (lanes == 0) break;
        stream_trace(it->accel, together, lanes, rays, has_hit, hits, found);
        for (int l = 0; l < lanes;) {
            ts->rays++;
            // The corners of a hit a few paths ahead start coming from memory while this one is shaded.
            if (l + SHADE_AHEAD < lanes && found[l + SHADE_AHEAD]) surface_prefetch(it->scene, &hits[l + SHADE_AHEAD]);
            if (path_vertex(pi, setup, &ps[l], &rays[l], &mpath[l], found[l], &hits[l], &gen[l], ts,
                            aovs ? &aov[l] : NULL) &&
                ++ps[l].depth < max_depth) {
                l++;
                continue;
            }
            finished[item[l] % WINDOW] = ps[l].radiance;
            if (aovs) finished_aov[item[l] % WINDOW] = aov[l];
            is_finished[item[l] % WINDOW] = true;
            // The last path in flight takes this place, with its hit still to be shaded.
            lanes--;
            ps[l] = ps[lanes], rays[l] = rays[lanes], mpath[l] = mpath[lanes];
            gen[l] = gen[lanes], item[l] = item[lanes];
            hits[l] = hits[lanes], found[l] = found[lanes];
            if (aovs) aov[l] = aov[lanes];
        }
        for (; added < items && is_finished[added % WINDOW]; added++) {
            if (tile_pass_stopping(tp)) {
                film_tile_stop(&t);
                *ft = t;
                return false;
            }
            int k = added % WINDOW;
            is_finished[k] = false;
            if (!(aovs ? film_tile_add_aov(&t, finished[k], &finished_aov[k]) : film_tile_add(&t, finished[k]))) {
                *ft = t;
                return true;
            }
        }
    }
    *ft = t;
    return true;
}

// The tile loop without AOVs is kept free of the AOV bookkeeping (film_tile_add alone).
static bool path_render_tile_plain(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts) {
    return path_render_tile_with(it, tp, ft, ts, false);
}

static __attribute__((noinline)) bool path_render_tile_aov(const integrator *it, const tile_pass *tp, film_tile *ft,
                                                          thread_stats *ts) {
    return path_render_tile_with(it, tp, ft, ts, true);
}

// The stream loop for lean paths without AOVs: no code for lights, media or AOVs.
static bool path_render_tile_stream_lean(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts,
                                         path_stream *sp) {
    return path_render_tile_stream_with(it, tp, ft, ts, sp, true, false);
}

static __attribute__((noinline)) bool path_render_tile_stream_any(const integrator *it, const tile_pass *tp,
                                                                 film_tile *ft, thread_stats *ts, path_stream *sp) {
    return path_render_tile_stream_with(it, tp, ft, ts, sp, false, ft->film->aovs);
}

static bool path_render_tile(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts) {
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    // Without the memory for the stream loop, the one-by-one loop makes the same bytes.
    path_stream *sp = it->scene->settings.max_depth > 0 && accel_streams(it->accel) ? malloc(sizeof *sp) : NULL;
    if (sp) {
        bool more = path_lean(pi) && !ft->film->aovs ? path_render_tile_stream_lean(it, tp, ft, ts, sp)
                                                     : path_render_tile_stream_any(it, tp, ft, ts, sp);
        free(sp);
        return more;
    }
    if (ft->film->aovs) return path_render_tile_aov(it, tp, ft, ts);
    return path_render_tile_plain(it, tp, ft, ts);
}

static void path_release(integrator *it) {
    path_integrator *pi = (path_integrator *)(void *)it;
    light_sampler_release(&pi->lights);
    envmap_sampler_release(&pi->environment);
    free(pi);
}

integrator *path_create(const glint_scene *s, const accel *a, bool sample_area_lights, glint_error *err) {
    path_integrator *pi = malloc(sizeof *pi);
    // The index of emissive surfaces depends only on the scene: built once per render, before the threads start.
    if (!pi || !light_sampler_build(&pi->lights, s)) {
        free(pi);
        snprintf(err->message, sizeof err->message, "%s: out of memory while indexing the emissive surfaces", s->path);
        return NULL;
    }
    integrator_init(&pi->base, s, a);
    pi->base.sample = path_sample;
    pi->base.render_tile = path_render_tile;
    pi->base.release = path_release;
    pi->sampled = sample_area_lights && pi->lights.count > 0 ? &pi->lights : NULL;
    // The environment's distribution, when it is the background (a black map has none: nothing to sample).
    pi->env_sampled = NULL;
    memset(&pi->environment, 0, sizeof pi->environment);
    if (s->settings.background == BACKGROUND_ENVMAP && sample_area_lights &&
        envmap_sampler_build(&pi->environment, &s->environment))
        pi->env_sampled = &pi->environment;
    return &pi->base;
}
