// path.c — the path tracer of "Ray Tracing in One Weekend", iterative: a path traces at most max_depth
// rays, each surface scatters it by its material (material/scatter.h), and escaping rays see the
// background. At diffuse surfaces, point and directional lights are added by next-event estimation, and so
// are emissive quads and mesh triangles, combined with the BSDF samples that hit them by multiple importance
// sampling.
#include "integrator/integrator.h"
#include "integrator/spawn.h"
#include "material/scatter.h"

#include <math.h>
#include <stdlib.h>

static const float inv_pi = 0.318309886183791f;

/// An emissive triangle of a mesh instance, in world space (placed by the instance's transform at prepare time).
typedef struct tri_light {
    vec3 p0, e1, e2;   ///< corner and the edges to the other two corners
    vec3 n;            ///< unit normal of the world-space triangle, either side (for the area-to-solid-angle factor)
    float area;
    uint32_t instance; ///< scene instance, and the triangle in its mesh: for emission sides and texture coordinates
    uint32_t tri;
    uint32_t material;
} tri_light;

/// One light of the index: a scene quad, or a triangle of tris.
typedef struct light_ref {
    bool is_tri;
    uint32_t index; ///< into s->quads, or into path_lights.tris
} light_ref;

/// The scene's emissive quads and mesh triangles, indexed for next-event estimation (built by path_prepare).
struct path_lights {
    light_ref *lights;      ///< the lights, quads first in scene order, then triangles by instance and triangle
    float *cdf;             ///< cdf[i]: probability of choosing one of lights[0..i]; the last is 1
    float *select_pdf;      ///< per scene quad: probability of choosing it, 0 for a quad that is not a light
    size_t count;           ///< lights
    size_t quad_count;      ///< scene quads when indexed (select_pdf's length)
    tri_light *tris;        ///< the emissive triangles
    size_t tri_count;
    size_t *tri_base;       ///< per scene instance: its first triangle's entry in tri_select_pdf, or SIZE_MAX
    float *tri_select_pdf;  ///< per triangle of each instance with a tri_base: probability of choosing it, or 0
    size_t instance_count;  ///< scene instances when indexed (tri_base's length)
};

void path_release(glint_scene *s) {
    path_lights *pl = s->path_lights;
    if (!pl) return;
    free(pl->lights);
    free(pl->cdf);
    free(pl->select_pdf);
    free(pl->tris);
    free(pl->tri_base);
    free(pl->tri_select_pdf);
    free(pl);
    s->path_lights = NULL;
}

// Power of a light of material m and area `area` up to constant factors (area times summed emission), by
// which lights are chosen; 0 for one that emits nothing. Emission textures scale this, but any positive
// choice stays unbiased.
static double light_power(const material *m, double area) {
    if (m->kind != MAT_DIFFUSE_LIGHT) return 0.0;
    double e = (double)m->emission.x + m->emission.y + m->emission.z;
    double p = e * area;
    return isfinite(p) && p > 0.0 ? p : 0.0;
}

// A quad light's power (light_power).
static double quad_light_power(const glint_scene *s, const quad *q) {
    return light_power(&s->materials[q->material], q->area);
}

// The scene material of triangle `tri` of mesh instance `in`, as surface_at_general chooses it.
static uint32_t instance_triangle_material(const glint_scene *s, const instance *in, size_t tri) {
    const scene_mesh *sm = &s->meshes[in->index];
    int32_t slot = sm->geometry.triangles[tri].material;
    if (in->material >= 0) return (uint32_t)in->material;
    if (slot >= 0 && (size_t)slot < sm->slot_count) return sm->slot_material[slot];
    return sm->default_material;
}

// Triangle `tri` of mesh instance `ii` in world space, with its power (light_power; 0: not a light).
static double tri_light_make(const glint_scene *s, uint32_t ii, uint32_t tri, tri_light *out) {
    const instance *in = &s->instances[ii];
    const material *m = &s->materials[instance_triangle_material(s, in, tri)];
    if (m->kind != MAT_DIFFUSE_LIGHT) return 0.0; // most triangles: skip the transform
    vec3 p0, p1, p2;
    mesh_triangle_positions(&s->meshes[in->index].geometry, tri, &p0, &p1, &p2);
    p0 = mat4_apply_point(&in->xf.m, p0);
    p1 = mat4_apply_point(&in->xf.m, p1);
    p2 = mat4_apply_point(&in->xf.m, p2);
    out->p0 = p0;
    out->e1 = v3_sub(p1, p0);
    out->e2 = v3_sub(p2, p0);
    vec3 c = v3_cross(out->e1, out->e2);
    float len = sqrtf(v3_len2(c));
    out->area = 0.5f * len;
    if (!(len > 0.0f) || !isfinite(len)) return 0.0; // degenerate: BSDF sampling alone finds it (never)
    out->n = v3_scale(c, 1.0f / len);
    out->instance = ii;
    out->tri = tri;
    out->material = (uint32_t)(m - s->materials);
    return light_power(m, out->area);
}

// Adds a light of power p to the cdf under construction; its selection probability (the cdf step, so that
// sampling and the MIS weights of BSDF hits agree on it).
static float add_light(path_lights *pl, light_ref ref, double p, double *sum, double total, size_t count,
                       float *prev) {
    *sum += p;
    size_t k = pl->count++;
    pl->lights[k] = ref;
    pl->cdf[k] = pl->count == count ? 1.0f : (float)(*sum / total);
    float select = pl->cdf[k] - *prev;
    *prev = pl->cdf[k];
    return select;
}

bool path_prepare(glint_scene *s) {
    path_release(s);
    size_t count = 0, tri_count = 0, tri_slots = 0;
    double total = 0.0;
    for (size_t i = 0; i < s->quad_count; i++) {
        double p = quad_light_power(s, &s->quads[i]);
        count += p > 0.0;
        total += p;
    }
    for (size_t i = 0; i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        if (in->kind != INSTANCE_MESH) continue;
        size_t nt = s->meshes[in->index].geometry.triangle_count, here = 0;
        for (size_t t = 0; t < nt; t++) {
            tri_light tl;
            double p = tri_light_make(s, (uint32_t)i, (uint32_t)t, &tl);
            here += p > 0.0;
            total += p;
        }
        tri_count += here;
        if (here) tri_slots += nt;
    }
    count += tri_count;
    if (count == 0 || !isfinite(total)) return true; // nothing to sample: BSDF sampling alone
    path_lights *pl = calloc(1, sizeof *pl);
    if (!pl) return false;
    s->path_lights = pl;
    pl->lights = malloc(count * sizeof *pl->lights);
    pl->cdf = malloc(count * sizeof *pl->cdf);
    pl->select_pdf = calloc(s->quad_count ? s->quad_count : 1, sizeof *pl->select_pdf);
    bool ok = pl->lights && pl->cdf && pl->select_pdf;
    if (ok && tri_count) {
        pl->tris = malloc(tri_count * sizeof *pl->tris);
        pl->tri_base = malloc(s->instance_count * sizeof *pl->tri_base);
        pl->tri_select_pdf = calloc(tri_slots, sizeof *pl->tri_select_pdf);
        ok = pl->tris && pl->tri_base && pl->tri_select_pdf;
    }
    if (!ok) {
        path_release(s);
        return false;
    }
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < s->quad_count; i++) {
        double p = quad_light_power(s, &s->quads[i]);
        if (!(p > 0.0)) continue;
        pl->select_pdf[i] = add_light(pl, (light_ref){false, (uint32_t)i}, p, &sum, total, count, &prev);
    }
    pl->quad_count = s->quad_count;
    if (!tri_count) return true;
    size_t slot = 0;
    for (size_t i = 0; i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        pl->tri_base[i] = SIZE_MAX;
        if (in->kind != INSTANCE_MESH) continue;
        size_t nt = s->meshes[in->index].geometry.triangle_count;
        for (size_t t = 0; t < nt; t++) {
            tri_light tl;
            double p = tri_light_make(s, (uint32_t)i, (uint32_t)t, &tl);
            if (!(p > 0.0)) continue;
            if (pl->tri_base[i] == SIZE_MAX) {
                pl->tri_base[i] = slot;
                slot += nt;
            }
            uint32_t k = (uint32_t)pl->tri_count++;
            pl->tris[k] = tl;
            pl->tri_select_pdf[pl->tri_base[i] + t] = add_light(pl, (light_ref){true, k}, p, &sum, total, count, &prev);
        }
    }
    pl->instance_count = s->instance_count;
    return true;
}

// Power heuristic weight (beta = 2) of a strategy of density a against one of density b, a > 0: a^2 /
// (a^2 + b^2), in a form that neither overflows nor divides zero by zero.
static float mis_weight(float a, float b) {
    float q = b / a;
    return 1.0f / (1.0f + q * q);
}

// Probability density, per unit solid angle, with which next-event estimation would have chosen the point
// where a ray of unit direction d hit an emissive quad or mesh triangle at distance t; 0 when it is not an
// indexed light.
static float light_pdf(const glint_scene *s, const path_lights *pl, const surface *sf, vec3 d, float t) {
    if (sf->kind == HIT_TRIANGLE) {
        if (sf->instance >= pl->instance_count || pl->tri_base[sf->instance] == SIZE_MAX) return 0.0f;
        float select = pl->tri_select_pdf[pl->tri_base[sf->instance] + sf->prim];
        if (!(select > 0.0f)) return 0.0f;
        // The light's record, found by binary search: its entries are sorted by (instance, triangle).
        size_t lo = 0, hi = pl->tri_count - 1;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            const tri_light *tm = &pl->tris[mid];
            if (tm->instance < sf->instance || (tm->instance == sf->instance && tm->tri < sf->prim)) lo = mid + 1;
            else hi = mid;
        }
        const tri_light *tl = &pl->tris[lo];
        float cos_l = fabsf(v3_dot(d, tl->n));
        if (!(cos_l > 0.0f)) return 0.0f;
        return select * t * t / (cos_l * tl->area);
    }
    if (sf->kind != HIT_QUAD || sf->instance != HIT_NO_INSTANCE || sf->prim >= pl->quad_count) return 0.0f;
    float select = pl->select_pdf[sf->prim];
    if (!(select > 0.0f)) return 0.0f;
    const quad *q = &s->quads[sf->prim];
    float cos_l = fabsf(v3_dot(d, q->normal));
    if (!(cos_l > 0.0f)) return 0.0f;
    return select * t * t / (cos_l * q->area);
}

// The emitted radiance of triangle light tl at barycentrics (b1, b2), point x, towards unit direction wi
// (from the receiver to the light): the side and texture coordinates as surface_at_general gives them to a
// ray that hits it there, so that both strategies see the same emission.
static vec3 tri_light_emitted(const glint_scene *s, const tri_light *tl, float b1, float b2, vec3 x, vec3 wi) {
    const instance *in = &s->instances[tl->instance];
    tri_hit th = {0.0f, 1.0f - b1 - b2, b1, b2};
    mesh_shading sh = mesh_shade(&s->meshes[in->index].geometry, tl->tri, &th);
    vec3 ng = mat4_apply_normal(&in->xf.inv, sh.ng);
    bool front = v3_dot(wi, ng) < 0.0f;
    return mat_emitted(&s->materials[tl->material], s->textures, front, sh.u, sh.v, x);
}

// Next-event estimation towards the emissive quads and triangles at a diffuse surface point: a light chosen
// by power, a uniform point on it and a shadow ray, weighted against BSDF sampling by the power heuristic.
// Returns Le cos / (pi pdf) times the weight; the caller multiplies by the albedo and the path's throughput.
// in_side is d.ng for the arriving ray d: light below the geometric surface does not count (the BSDF
// sampling does not continue there either).
static vec3 sample_light(const glint_scene *s, const path_lights *pl, const surface *sf, const spawn_point *sp,
                         float in_side, rng *r, thread_stats *ts) {
    float xi = rng_float(r), a = rng_float(r), b = rng_float(r);
    size_t lo = 0, hi = pl->count - 1; // the first light whose cdf exceeds xi
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (xi < pl->cdf[mid]) hi = mid;
        else lo = mid + 1;
    }
    float select = pl->cdf[lo] - (lo ? pl->cdf[lo - 1] : 0.0f); // as path_prepare recorded it
    light_ref ref = pl->lights[lo];
    vec3 x, n;
    float area;
    const tri_light *tl = NULL;
    float b1 = 0.0f, b2 = 0.0f;
    const quad *q = NULL;
    if (ref.is_tri) {
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
        le = tri_light_emitted(s, tl, b1, b2, x, wi);
        if (!(le.x > 0.0f || le.y > 0.0f || le.z > 0.0f)) return v3s(0.0f);
    }
    float cos_s = v3_dot(sf->n, wi);
    if (!(cos_l > 0.0f) || !(cos_s > 0.0f) || v3_dot(wi, sf->ng) * in_side > 0.0f) return v3s(0.0f);
    float pdf_light = (q ? pl->select_pdf[ref.index] : select) * d2 / (cos_l * area);
    if (!(pdf_light > 0.0f) || !isfinite(pdf_light)) return v3s(0.0f);
    // Stop short of the light by a relative margin (pbrt's shadow epsilon) so that it does not occlude itself.
    ray shadow = spawn_ray(sp, wi, 0.0f, dist * (1.0f - 1e-4f));
    ts->shadow_rays++;
    if (accel_occluded(s->accel, &shadow)) return v3s(0.0f);
    if (q) le = mat_emitted(&s->materials[q->material], s->textures, true, a, b, x);
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
    return path_trace(s, primary.o, primary.d, r, ts);
}

vec3 path_trace(const glint_scene *s, vec3 o, vec3 d, rng *r, thread_stats *ts) {
    ray cur = {o, d, 0.0f, INFINITY};
    vec3 radiance = v3s(0.0f), throughput = v3s(1.0f);
    bool has_lights = s->light_count > 0;
    const path_lights *pl = s->settings.no_light_sampling ? NULL : s->path_lights;
    bool light_sampled = false; // the last vertex sampled the area lights: a hit on one is weighted
    float bsdf_pdf = 0.0f;      // solid-angle density of the direction the last vertex sampled
    bool lean = !has_lights && !pl;
    // Whether cur.d has unit length: camera rays and the lean bounce's Lambertian directions are left unnormalised.
    bool unit = false;
    for (int depth = 0; depth < s->settings.max_depth; depth++) {
        hit h;
        ts->rays++;
        if (!accel_intersect(s->accel, &cur, &h)) {
            if (!unit) cur.d = v3_unit(cur.d);
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
                if (m->kind == MAT_LAMBERTIAN) {
                    // Only the direction matters to the next intersection: the normalisation (a square root
                    // and a division) waits until a mirror, glass or the background needs a unit vector.
                    ev.dir = mat_lambertian_sum(n, sample_sphere_uniform(r));
                    ev.weight = m->albedo;
                    unit = false;
                } else {
                    if (!unit) cur.d = v3_unit(cur.d);
                    unit = true;
                    if (!mat_scatter(m, m->albedo, cur.d, n, front, r, &ev)) break;
                }
                throughput = v3_mul(throughput, ev.weight);
                if (!(throughput.x > 0.0f || throughput.y > 0.0f || throughput.z > 0.0f)) break;
                spawn_point spt = spawn_point_sphere(p, n, sp->radius);
                cur = spawn_ray(&spt, ev.dir, 0.0f, INFINITY);
                continue;
            }
        }
        if (!unit) { // the general code below works with unit directions: the same ray, t in its units
            float len = v3_len(cur.d);
            cur.d = v3_scale(cur.d, 1.0f / len);
            h.t *= len;
            unit = true;
        }
        surface sf = surface_at(s, &cur, &h);
        const material *m = &s->materials[sf.material];
        if (m->kind == MAT_DIFFUSE_LIGHT) {
            vec3 le = mat_emitted(m, s->textures, sf.front, sf.u, sf.v, sf.p);
            if (light_sampled) {
                float pdf_light = light_pdf(s, pl, &sf, cur.d, h.t);
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
                vec3 direct = sample_light(s, pl, &sf, &sp, in_side, r, ts);
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
