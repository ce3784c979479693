// path.c — the path tracer of "Ray Tracing in One Weekend", iterative: a path traces at most max_depth
// rays, each surface scatters it by its material (material/bsdf.h: the book's materials through their own fast
// paths, material/scatter.h), and escaping rays see the background. At diffuse surfaces and at the glossy ones
// of the microfacet materials, point and directional lights are added by next-event estimation, and so
// are emissive quads, mesh triangles and spheres, combined with the BSDF samples that hit them by multiple
// importance sampling. Participating media (medium/medium.h) scatter paths inside them, and the same lights
// are sampled there with the phase function, their shadow rays carrying the media's transmittance.
#include "integrator/path.h"
#include "integrator/alpha_mask.h"
#include "integrator/light_sampler.h"
#include "integrator/nee.h"
#include "integrator/sample_stream.h"
#include "integrator/spawn.h"
#include "integrator/surface.h"
#include "material/bsdf.h"

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
    bool light_only; ///< (tests) microfacet vertices: light sampling alone, no MIS (integrator_options)
} path_integrator;

// Book 3's mixture density for a diffuse bounce in a scene with "importance" spheres: half the directions
// from the cosine lobe (the one mat_scatter drew), half towards one of those spheres (uniform in the cone it
// subtends). The weight becomes BRDF x cos / mixture density, and the mixture density, returned, is what MIS
// weighs a hit on a light with. A direction below the surface ends the path (weight 0).
static float aim_diffuse(const glint_scene *s, vec3 p, vec3 n, rng *r, scatter_event *ev) {
    size_t count = s->importance_sphere_count;
    rng_decision(r, RNG_DIM_IMPORTANCE);
    if (rng_float(r) < 0.5f) {
        size_t i = (size_t)(rng_float(r) * (float)count);
        float a, b, dist, pdf;
        rng_float2(r, &a, &b);
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
    uint32_t occluder;        ///< what blocked the path's last shadow ray (accel_occluded_hinted)
} path_state;

// A path that has traced nothing yet.
static inline path_state path_start(film_aov_sample *aov) {
    path_state ps = {.radiance = v3s(0.0f), .throughput = v3s(1.0f), .aov_pending = aov != NULL,
                     .occluder = ACCEL_NO_OCCLUDER};
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
    unsigned ahead; ///< the Sobol' pairs a bounce draws first, computed before its ray is traced (rng_prepare)
} path_setup;

// The setup of pi's paths; known_lean (a constant after inlining, true only where path_lean holds) leaves the
// code for lights and media out of the vertices that use it.
static inline path_setup path_setup_of(const path_integrator *pi, bool known_lean) {
    const glint_scene *s = pi->base.scene;
    if (known_lean) return (path_setup){false, NULL, NULL, 0, true, RNG_AHEAD_BSDF};
    unsigned ahead = RNG_AHEAD_BSDF | (pi->sampled ? RNG_AHEAD_LIGHT : 0u) |
                     (pi->env_sampled ? RNG_AHEAD_ENVIRONMENT : 0u) | (s->medium_count ? RNG_AHEAD_MEDIUM : 0u);
    return (path_setup){s->light_count > 0, pi->sampled, pi->env_sampled, s->medium_count, path_lean(pi), ahead};
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
static inline __attribute__((always_inline)) bool path_continue(path_state *ps, ray *cur, const spawn_point *sp,
                                                                vec3 weight, vec3 dir) {
    ps->throughput = v3_mul(ps->throughput, weight);
    if (!(ps->throughput.x > 0.0f || ps->throughput.y > 0.0f || ps->throughput.z > 0.0f)) return false;
    *cur = spawn_ray(sp, dir, 0.0f, INFINITY);
    return true;
}

// A lean path's Lambertian bounce (the book's n + u): the direction is not normalised, since only the direction
// matters to the next intersection; a mirror, glass or the background makes it a unit vector when it needs one.
static inline __attribute__((always_inline)) vec3 path_lean_lambertian(path_state *ps, vec3 n, rng *r) {
    ps->unit = false;
    return mat_lambertian_sum(n, sample_sphere_uniform(r));
}

// Next-event estimation at a vertex that scatters diffusely (nv: a surface or a point in a medium), with the
// vertex's scattering weight and the density of the direction it samples (dir_pdf, for MIS): the point and
// directional lights, then (where the path goes on, `more`, so that the two strategies cover the same paths) the
// emissive surfaces and the environment.
static inline __attribute__((always_inline)) void path_nee(const path_integrator *pi, path_setup setup,
                                                          path_state *ps, const nee_vertex *nv,
                                                          const spawn_point *sp, vec3 weight, float dir_pdf,
                                                          bool more, rng *r, thread_stats *ts) {
    const integrator *it = &pi->base;
    ps->light_sampled = ps->env_sampled = false;
    if (setup.has_lights)
        ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, nee_point_lights(it, sp, nv, weight, ts)));
    if (setup.pl && more) {
        vec3 direct = nee_area_lights(it, setup.pl, nv, sp, r, ts);
        ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, v3_mul(weight, direct)));
        ps->light_sampled = true;
        ps->bsdf_pdf = dir_pdf;
    }
    if (setup.es && more) {
        vec3 direct = nee_environment(it, setup.es, nv, sp, r, ts);
        ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, v3_mul(weight, direct)));
        ps->env_sampled = true;
        ps->bsdf_pdf = dir_pdf;
    }
}

// The ray's free flight through the media up to the surface it meets (found: at h->t) or to infinity. Returns 1
// when it scatters in a medium (lights sampled there, the next ray drawn from the phase function), 0 when the
// path ends (black throughput), -1 when it reaches the surface or the background (the throughput attenuated).
static inline __attribute__((always_inline)) int path_medium_step(const path_integrator *pi, path_setup setup,
                                                                 path_state *ps, ray *cur, medium_path *mpath,
                                                                 bool found, hit *h, rng *r, thread_stats *ts) {
    const glint_scene *s = pi->base.scene;
    if (!ps->unit) { // distances in the media are lengths: a unit direction, t in its units
        float len = v3_len(cur->d);
        cur->d = v3_scale(cur->d, 1.0f / len);
        if (found) h->t *= len;
        ps->unit = true;
    }
    rng_decision(r, RNG_DIM_MEDIUM);
    medium_event me = medium_sample(s->media, setup.media, s->textures, cur->o, cur->d, found ? h->t : INFINITY,
                                    mpath, r);
    rng_decision(r, RNG_DIM_BSDF); // the surface's scattering, or the phase function's, draws next
    ps->throughput = v3_mul(ps->throughput, me.weight);
    if (!(ps->throughput.x > 0.0f || ps->throughput.y > 0.0f || ps->throughput.z > 0.0f)) return 0;
    if (!me.scattered) return -1;
    // It scatters in the medium: the lights are sampled as at a diffuse surface, with the phase function in place
    // of the BSDF (weight 1), and the next direction is drawn from the phase function.
    float g = s->media[me.index].g;
    nee_vertex nv = {NULL, 0.0f, cur->d, g, NULL, v3s(0.0f), false, &ps->occluder};
    spawn_point mp = {me.p, v3s(0.0f), 0.0f, cur->time}; // no surface to step off; the path's time
    path_nee(pi, setup, ps, &nv, &mp, v3s(1.0f), 0.0f, ps->depth + 1 < s->settings.max_depth, r, ts);
    rng_decision(r, RNG_DIM_BSDF);
    float a, b;
    rng_float2(r, &a, &b);
    vec3 wi = phase_hg_sample(g, cur->d, a, b);
    ps->bsdf_pdf = phase_hg(g, v3_dot(cur->d, wi));
    *cur = (ray){me.p, wi, 0.0f, INFINITY, cur->time};
    return 1;
}

// The background a ray *cur that met nothing sees, weighted against the environment's sampling at the last
// vertex; the path ends there.
static inline __attribute__((always_inline)) void path_escape(const glint_scene *s, path_setup setup,
                                                             path_state *ps, ray *cur, film_aov_sample *aov) {
    if (!ps->unit) cur->d = v3_unit(cur->d);
    vec3 bg = scene_background(s, cur->d);
    // The background seen (through mirrors and glass) is the albedo; the normal stays (0 for no surface).
    if (ps->aov_pending) aov->albedo = integrator_aov_albedo(v3_mul(ps->throughput, bg));
    if (ps->env_sampled) bg = v3_scale(bg, nee_mis_weight(ps->bsdf_pdf, envmap_pdf(setup.es, &s->environment, cur->d)));
    ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, bg));
}

// A lean path at a world sphere of an untextured material that does not emit (the book's scenes): the sphere's
// own hit frame in place of the surface record, which with texture lookups, emission, shading normals and light
// sampling costs as much as the bounce itself; the bounce is the general vertex's. -1 when the sphere is not such
// a one, else whether the path goes on.
static inline __attribute__((always_inline)) int path_lean_sphere(const glint_scene *s, path_state *ps, ray *cur,
                                                                 const hit *h, rng *r, film_aov_sample *aov) {
    const sphere *sp = &s->spheres[h->prim];
    const material *m = &s->materials[sp->material];
    if (m->kind >= MAT_DIFFUSE_LIGHT || m->albedo_texture >= 0) return -1; // emitters and microfacet materials
    vec3 p, n;
    sphere_hit_frame(sp, cur, h->t, &p, &n);
    bool front = v3_dot(cur->d, n) < 0.0f;
    if (!front) n = v3_neg(n);
    if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, m->albedo, n, m);
    scatter_event ev;
    if (m->kind == MAT_LAMBERTIAN) {
        ev.dir = path_lean_lambertian(ps, n, r);
        ev.weight = m->albedo;
    } else {
        if (!ps->unit) cur->d = v3_unit(cur->d);
        ps->unit = true;
        if (!mat_scatter(m, m->albedo, cur->d, n, front, r, &ev)) return 0;
    }
    spawn_point spt = spawn_point_sphere(p, n, sp->radius, cur->time);
    return path_continue(ps, cur, &spt, ev.weight, ev.dir);
}

// A lean path at an untextured Lambertian quad or mesh (the floors and models of most scenes, surface_at_flat):
// the general vertex's bounce without its texture lookup, emitter test and light sampling, which cost 5 % on
// the bunny. Whether the path goes on.
static inline __attribute__((always_inline)) bool path_lean_flat(const glint_scene *s, path_state *ps, ray *cur,
                                                                const surface *sf, const material *m, rng *r,
                                                                film_aov_sample *aov) {
    if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, m->albedo, sf->n, m);
    vec3 dir = path_lean_lambertian(ps, sf->n, r);
    if (path_crosses(sf, v3_dot(cur->d, sf->ng), dir, false)) return false;
    spawn_point sp = spawn_point_of(s, sf);
    return path_continue(ps, cur, &sp, m->albedo, dir);
}

// An emitter ends the path: its emission, weighted against the area lights' sampling at the last vertex.
static inline __attribute__((always_inline)) void path_emitter(const glint_scene *s, path_setup setup,
                                                              path_state *ps, const ray *cur, const hit *h,
                                                              const surface *sf, const material *m,
                                                              film_aov_sample *aov) {
    vec3 tp = surface_texture_point(s, sf, m->emission_texture);
    vec3 le = mat_emitted(m, s->textures, sf->front, sf->u, sf->v, tp);
    if (ps->aov_pending) {
        aov->albedo = integrator_aov_albedo(v3_mul(ps->throughput, integrator_aov_emitter(le)));
        aov->normal = sf->n;
    }
    if (ps->light_sampled) {
        float pdf_light = light_sampler_pdf(setup.pl, s, sf, cur->o, cur->d, h->t);
        if (pdf_light > 0.0f) le = v3_scale(le, nee_mis_weight(ps->bsdf_pdf, pdf_light));
    }
    ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, le));
}

// A tangent frame at sf for anisotropy and normal maps: along u and v on world quads, along increasing longitude
// on world spheres (about the y axis, as sphere_uv), dp/du and dp/dv of a mesh triangle with texture coordinates
// (per triangle: MikkTSpace's face tangents, not its per-vertex averages), none elsewhere (bsdf_init then takes
// any).
static void path_tangents(const glint_scene *s, const surface *sf, vec3 *t, vec3 *b) {
    *t = *b = v3s(0.0f);
    if (sf->kind == HIT_TRIANGLE && sf->instance < s->instance_count) {
        const instance *in = &s->instances[sf->instance];
        const mesh *mh = &s->meshes[in->index].geometry;
        mesh_corners uc = mesh_triangle_uvs(mh, sf->prim);
        if (!mesh_corners_complete(uc)) return;
        vec3 p0, p1, p2;
        mesh_triangle_positions(mh, sf->prim, &p0, &p1, &p2);
        uv2 a = mh->uvs[uc.i[0]], bb = mh->uvs[uc.i[1]], c = mh->uvs[uc.i[2]];
        vec3 e1 = v3_sub(p1, p0), e2 = v3_sub(p2, p0);
        float du1 = bb.u - a.u, dv1 = bb.v - a.v, du2 = c.u - a.u, dv2 = c.v - a.v;
        float det = du1 * dv2 - du2 * dv1;
        if (!(fabsf(det) > 1e-20f)) return;
        float inv = 1.0f / det;
        *t = mat4_apply_vector(&in->xf.m, v3_scale(v3_sub(v3_scale(e1, dv2), v3_scale(e2, dv1)), inv));
        *b = mat4_apply_vector(&in->xf.m, v3_scale(v3_sub(v3_scale(e2, du1), v3_scale(e1, du2)), inv));
        return;
    }
    if (sf->instance != HIT_NO_INSTANCE) return;
    if (sf->kind == HIT_QUAD) {
        const quad *q = &s->quads[sf->prim];
        *t = q->u;
        *b = q->v;
    } else if (sf->kind == HIT_SPHERE) {
        vec3 out = sf->front ? sf->ng : v3_neg(sf->ng);
        *t = v3(-out.z, 0.0f, out.x); // y x outward
    }
}

// A path at a surface of a microfacet material (conductor, rough_dielectric, pbr) or, in a scene with lights, the
// book's fuzzed metal (material_uses_bsdf), kept out of the fast vertex:
// pbr's emission (weighted against the light sampling of the last vertex, as an emitter's), the material's BSDF
// at the point, a direction sampled from it and, where it has glossy or diffuse lobes, next-event estimation
// with MIS against that sample. Whether the path goes on.
static __attribute__((noinline)) bool path_bsdf_vertex(const path_integrator *pi, path_setup setup, path_state *ps,
                                                      ray *cur, const hit *h, const surface *sf, const material *m,
                                                      rng *r, thread_stats *ts, film_aov_sample *aov) {
    const glint_scene *s = pi->base.scene;
    if (material_emits(m)) {
        vec3 tp = surface_texture_point(s, sf, m->emission_texture);
        vec3 le = mat_emitted(m, s->textures, sf->front, sf->u, sf->v, tp);
        if (ps->light_sampled) {
            float pdf_light = light_sampler_pdf(setup.pl, s, sf, cur->o, cur->d, h->t);
            if (pdf_light > 0.0f) le = v3_scale(le, nee_mis_weight(ps->bsdf_pdf, pdf_light));
        }
        ps->radiance = v3_add(ps->radiance, v3_mul(ps->throughput, le));
    }
    vec3 tp = surface_texture_point(s, sf, 0);
    vec3 albedo = mat_albedo(m, s->textures, sf->u, sf->v, tp);
    bsdf_site site = {sf->n, v3s(0.0f), v3s(0.0f), sf->u, sf->v, tp, sf->front};
    path_tangents(s, sf, &site.tangent, &site.bitangent);
    bsdf b;
    bsdf_init(&b, m, s->textures, albedo, &site);
    // The base colour the BSDF shades with (a texture times glTF's baseColorFactor), not the texture alone.
    if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, b.base, sf->n, m);
    vec3 wo = v3_neg(cur->d);
    // The direction first, then the lights: next-event estimation counts whether or not the sample is absorbed
    // (a rough lobe at a grazing angle loses many below the horizon, and the light they would have found is
    // next-event estimation's to add).
    bsdf_sample_record bs;
    bool scattered = bsdf_sample(&b, wo, r, &bs);
    spawn_point sp = spawn_point_of(s, sf);
    float in_side = v3_dot(cur->d, sf->ng);
    if (bsdf_has_nee(&b)) {
        nee_vertex nv = {sf, in_side, cur->d, 0.0f, &b, wo, pi->light_only, &ps->occluder};
        path_nee(pi, setup, ps, &nv, &sp, v3s(1.0f), scattered ? bs.pdf : 0.0f,
                 ps->depth + 1 < s->settings.max_depth, r, ts);
        if (!scattered) return false;
        // A delta lobe's direction cannot be found by light sampling: what it hits counts in full. Light sampling
        // alone (tests): what the BSDF's own samples hit adds nothing.
        if (bs.flags & BSDF_DELTA) ps->light_sampled = ps->env_sampled = false;
        else if (pi->light_only) ps->bsdf_pdf = 0.0f, ps->env_sampled = false;
    } else {
        ps->light_sampled = ps->env_sampled = false;
        if (!scattered) return false;
    }
    if (path_crosses(sf, in_side, bs.wi, (bs.flags & BSDF_TRANSMISSION) != 0)) return false;
    return path_continue(ps, cur, &sp, bs.weight, bs.wi);
}

// What the path does where its ray *cur ends, at hit *h (found; by address, as the query wrote it: a copy would
// load it whole, which waits for the query's stores to retire) or in the background, at depth ps->depth:
// gathers light into ps->radiance and makes the next ray. False when the path ends there. Lean paths (setup.lean)
// take the spheres' and flat surfaces' own frames (path_lean_sphere, surface_at_flat) and the book's Lambertian
// bounce (path_lean_flat); every vertex ends in the same steps (path_aov_surface, path_nee, path_continue).
static inline __attribute__((always_inline)) bool path_vertex(const path_integrator *pi, path_setup setup,
                                                             path_state *ps, ray *cur, medium_path *mpath, bool found,
                                                             hit *h, rng *r, thread_stats *ts, film_aov_sample *aov) {
    const glint_scene *s = pi->base.scene;
    bool lean = setup.lean;
    rng_start_bounce(r, ps->depth); // the Sobol' sampler's dimensions of this bounce
    if (setup.media) {
        int scattered = path_medium_step(pi, setup, ps, cur, mpath, found, h, r, ts);
        if (scattered >= 0) return scattered != 0;
    }
    if (!found) {
        path_escape(s, setup, ps, cur, aov);
        return false;
    }
    if (aov && ps->depth == 0) aov->depth = ps->unit ? h->t : h->t * v3_len(cur->d); // camera rays: unnormalised
    if (lean && h->kind == HIT_SPHERE && h->instance == HIT_NO_INSTANCE) {
        int more = path_lean_sphere(s, ps, cur, h, r, aov);
        if (more >= 0) return more != 0;
    }
    // The general code below works with unit directions: the same ray, t in its units. A lean path's Lambertian
    // surface needs none (the book's n + u, as at spheres above): it waits until the material is known.
    if (!ps->unit && !lean) path_unit_direction(ps, cur, h);
    surface sf;
    bool flat = lean && surface_at_flat(s, cur, h, &sf);
    if (!flat) surface_at_into(s, cur, h, &sf);
    const material *m = &s->materials[sf.material];
    if (flat && m->kind == MAT_LAMBERTIAN && m->albedo_texture < 0) return path_lean_flat(s, ps, cur, &sf, m, r, aov);
    bool lean_diffuse = lean && m->kind == MAT_LAMBERTIAN;
    if (!ps->unit && !lean_diffuse) path_unit_direction(ps, cur, h);
    if (m->kind == MAT_DIFFUSE_LIGHT) {
        path_emitter(s, setup, ps, cur, h, &sf, m, aov);
        return false;
    }
    if (material_uses_bsdf(m, setup.has_lights || setup.pl || setup.es))
        return path_bsdf_vertex(pi, setup, ps, cur, h, &sf, m, r, ts, aov);
    vec3 albedo = mat_albedo(m, s->textures, sf.u, sf.v, surface_texture_point(s, &sf, m->albedo_texture));
    if (ps->aov_pending) ps->aov_pending = path_aov_surface(aov, ps->throughput, albedo, sf.n, m);
    scatter_event ev;
    if (lean_diffuse) { // mat_scatter's direction, not normalised: the next ray's direction needs no unit length
        ev = (scatter_event){path_lean_lambertian(ps, sf.n, r), albedo, true, false};
    } else if (!mat_scatter(m, albedo, cur->d, sf.n, sf.front, r, &ev)) {
        return false;
    }
    spawn_point sp = spawn_point_of(s, &sf);
    float in_side = v3_dot(cur->d, sf.ng);
    if (ev.diffuse) {
        float dir_pdf = s->importance_sphere_count ? aim_diffuse(s, sp.p, sf.n, r, &ev)
                                                   : v3_dot(ev.dir, sf.n) * inv_pi;
        nee_vertex nv = {&sf, in_side, cur->d, 0.0f, NULL, v3s(0.0f), false, &ps->occluder};
        path_nee(pi, setup, ps, &nv, &sp, ev.weight, dir_pdf, ps->depth + 1 < s->settings.max_depth, r, ts);
    } else {
        ps->light_sampled = ps->env_sampled = false;
    }
    if (path_crosses(&sf, in_side, ev.dir, ev.transmitted)) return false;
    return path_continue(ps, cur, &sp, ev.weight, ev.dir);
}

// The radiance a path starting with the primary ray (origin o, direction d, all t > 0, at `time`) carries, and its AOVs
// when aov is not NULL (a scheduler_trace_fn). The ray comes by its parts, in registers: a whole ray passed by value
// is copied with wide loads that cannot be forwarded from the stores that just made it. d need not have unit length.
// One copy: the AOV tests are predictable branches on a NULL pointer (a second, specialised copy cost the sphere
// scenes 12 % through gcc's inlining budget).
static vec3 path_trace(const integrator *it, vec3 o, vec3 d, float time, rng *r, thread_stats *ts,
                       film_aov_sample *aov, const hit *first, bool first_found) {
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    const glint_scene *s = pi->base.scene;
    path_setup setup = path_setup_of(pi, false);
    path_state ps = path_start(aov);
    ray cur = {o, d, 0.0f, INFINITY, time};
    medium_path mpath = medium_path_start();
    for (; ps.depth < s->settings.max_depth; ps.depth++) {
        hit h;
        ts->rays++;
        rng_prepare(r, ps.depth, setup.ahead); // beside the traversal below, which does not wait for it
        bool found;
        if (first && ps.depth == 0) { // the camera ray, traced with its neighbours (accel_intersect_coherent)
            h = *first;
            found = first_found;
        } else {
            found = pi->base.alpha_masks ? alpha_intersect(pi->base.accel, s, &cur, &h)
                                         : accel_intersect(pi->base.accel, &cur, &h);
        }
        if (!path_vertex(pi, setup, &ps, &cur, &mpath, found, &h, r, ts, aov)) break;
    }
    return ps.radiance;
}

// One sample of pixel (x, y): its camera ray, then its path (what the tile loops do sixteen at a time).
static vec3 path_sample(const integrator *it, int x, int y, uint32_t sample, rng *r, thread_stats *ts,
                        film_aov_sample *aov) {
    (void)sample;
    ray primary = camera_sample_ray(&it->camera, x, y, r);
    return path_trace(it, primary.o, primary.d, primary.time, r, ts, aov, NULL, false);
}

/// The stream loop's memory: the scheduler's lanes and, beside them, the rest of each path's state, by lane.
typedef struct path_lanes {
    scheduler_stream stream;
    path_state ps[SCHEDULER_STREAM];
    medium_path mpath[SCHEDULER_STREAM];
} path_lanes;

/// The stream loop's paths as the scheduler sees them (scheduler_paths): a local of the tile function, so that once
/// the steps are inlined its fields live in registers.
struct scheduler_paths {
    const path_integrator *pi;
    path_setup setup;
    int max_depth;
    path_state *ps;
    medium_path *mpath;
    bool pcg; ///< every path draws PCG32 numbers (a constant of the loop: rng_assume_pcg)
};

// A new path in a lane of the stream.
static inline __attribute__((always_inline)) void scheduler_paths_start(scheduler_paths *p, int lane,
                                                                       film_aov_sample *aov) {
    p->ps[lane] = path_start(aov);
    p->mpath[lane] = medium_path_start();
}

// One vertex of a lane's path, which goes on while it is under the depth limit, with a local generator at the
// lane's position. A hit's first Sobol' pairs are computed as the step starts (rng_prepare), beside the surface's
// lookup rather than after it: the bunny with Sobol' numbers 1.015 and 1.041, many-lights 1.049. Not earlier, at
// the step before: the values would have to wait in the lanes, and 48-byte lanes cost the bunny 5 %.
static inline __attribute__((always_inline)) bool scheduler_paths_step(scheduler_paths *p, int lane, ray *cur,
                                                                      bool found, hit *h, rng_position *at,
                                                                      thread_stats *ts, film_aov_sample *aov) {
    rng g = rng_join(*at, NULL);
    if (p->pcg) rng_assume_pcg(&g); // the vertex's draws lose their sampler test
    if (found) rng_prepare(&g, p->ps[lane].depth, p->setup.ahead); // nothing for PCG32
    bool more = path_vertex(p->pi, p->setup, &p->ps[lane], cur, &p->mpath[lane], found, h, &g, ts, aov) &&
                ++p->ps[lane].depth < p->max_depth;
    *at = rng_position_of(&g);
    return more;
}

// What a lane's path gathered.
static inline __attribute__((always_inline)) vec3 scheduler_paths_radiance(const scheduler_paths *p, int lane) {
    return p->ps[lane].radiance;
}

// A lane's path moves to another lane.
static inline __attribute__((always_inline)) void scheduler_paths_move(scheduler_paths *p, int to, int from) {
    p->ps[to] = p->ps[from], p->mpath[to] = p->mpath[from];
}

// The stream loop with the path tracer's steps; `lean` (a constant): path_lean holds; `pcg` (a constant): the
// generators are PCG32. A depth limit of at least 1.
static inline __attribute__((always_inline)) bool path_render_tile_stream_with(const integrator *it,
                                                                              const tile_pass *tp, film_tile *ft,
                                                                              thread_stats *ts, path_lanes *pl,
                                                                              bool lean, bool aovs, bool pcg) {
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    scheduler_paths paths = {pi, path_setup_of(pi, lean), it->scene->settings.max_depth, pl->ps, pl->mpath, pcg};
    return scheduler_tile_stream(it, tp, ft, ts, &pl->stream, aovs, &paths);
}

// The tile loop without AOVs is kept free of the AOV bookkeeping (film_tile_add alone).
static bool path_render_tile_plain(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts) {
    return scheduler_tile_batched(it, tp, ft, ts, false, path_trace);
}

static __attribute__((noinline)) bool path_render_tile_aov(const integrator *it, const tile_pass *tp, film_tile *ft,
                                                          thread_stats *ts) {
    return scheduler_tile_batched(it, tp, ft, ts, true, path_trace);
}

// The stream loop for lean paths without AOVs: no code for lights, media or AOVs.
static bool path_render_tile_stream_lean(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts,
                                         path_lanes *pl) {
    return path_render_tile_stream_with(it, tp, ft, ts, pl, true, false, false);
}

// The same with PCG32 numbers (the independent sampler, the mesh yardstick's): no Sobol' branches in its draws
// (the bunny 1.021 in 11 pairs, 0.992 in 21: within the noise, and no cost). Only here: a PCG32 copy of
// path_trace cost the sphere scenes 6 % (gcc's inlining budget).
static __attribute__((noinline)) bool path_render_tile_stream_lean_pcg(const integrator *it, const tile_pass *tp,
                                                                      film_tile *ft, thread_stats *ts,
                                                                      path_lanes *pl) {
    return path_render_tile_stream_with(it, tp, ft, ts, pl, true, false, true);
}

static __attribute__((noinline)) bool path_render_tile_stream_any(const integrator *it, const tile_pass *tp,
                                                                 film_tile *ft, thread_stats *ts, path_lanes *pl) {
    return path_render_tile_stream_with(it, tp, ft, ts, pl, false, ft->film->aovs, false);
}

// The path tracer's render_tile: its paths in streams where the tree is big enough to gain from them
// (accel_streams), else one by one after their camera rays are made in batches.
static bool path_render_tile(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts) {
    const path_integrator *pi = (const path_integrator *)(const void *)it;
    // Without the memory for the stream loop, the one-by-one loop makes the same bytes. Alpha masks take the
    // one-by-one loop: the stream's queries (accel_intersect_stream) know nothing of them (alpha_mask.h).
    path_lanes *pl = it->scene->settings.max_depth > 0 && !it->alpha_masks && accel_streams(it->accel)
                         ? malloc(sizeof *pl) : NULL;
    if (pl) {
        bool lean = path_lean(pi) && !ft->film->aovs;
        bool more = !lean                            ? path_render_tile_stream_any(it, tp, ft, ts, pl)
                    : it->stream == RNG_SOBOL_STREAM ? path_render_tile_stream_lean(it, tp, ft, ts, pl)
                                                     : path_render_tile_stream_lean_pcg(it, tp, ft, ts, pl);
        free(pl);
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

integrator *path_create(const glint_scene *s, const accel *a, const integrator_options *o, glint_error *err) {
    bool sample_area_lights = !(o && o->no_light_sampling);
    path_integrator *pi = malloc(sizeof *pi);
    // The index of emissive surfaces depends only on the scene: built once per render, before the threads start.
    if (!pi || !light_sampler_build(&pi->lights, s, !(o && o->no_light_tree))) {
        free(pi);
        snprintf(err->message, sizeof err->message, "%s: out of memory while indexing the emissive surfaces", s->path);
        return NULL;
    }
    integrator_init(&pi->base, s, a);
    pi->base.sample = path_sample;
    pi->base.render_tile = path_render_tile;
    pi->base.release = path_release;
    pi->sampled = sample_area_lights && pi->lights.count > 0 ? &pi->lights : NULL;
    pi->light_only = o && o->light_sampling_only;
    // The environment's distribution, when it is the background (a black map has none: nothing to sample).
    pi->env_sampled = NULL;
    memset(&pi->environment, 0, sizeof pi->environment);
    if (s->settings.background == BACKGROUND_ENVMAP && sample_area_lights &&
        envmap_sampler_build(&pi->environment, &s->environment))
        pi->env_sampled = &pi->environment;
    return &pi->base;
}
