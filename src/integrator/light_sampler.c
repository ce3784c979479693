// light_sampler.c — building the index of emissive quads and triangles, and the densities of its choices.
#include "integrator/light_sampler.h"
#include "integrator/alpha_mask.h"
#include "material/scatter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void light_sampler_release(light_sampler *pl) {
    free(pl->lights);
    free(pl->cdf);
    free(pl->select_pdf);
    free(pl->tris);
    free(pl->tri_base);
    free(pl->tri_select_pdf);
    free(pl->sphere_select_pdf);
    free(pl->quad_light);
    free(pl->sphere_light);
    light_tree_release(&pl->tree);
    memset(pl, 0, sizeof *pl);
}

// Power of a light of material m and area `area` up to constant factors (area times summed emission), by
// which lights are chosen; 0 for one that emits nothing. Emission textures scale this, but any positive
// choice stays unbiased.
static double light_power(const material *m, double area) {
    if (!material_emits(m)) return 0.0;
    double e = (double)m->emission.x + m->emission.y + m->emission.z;
    double p = e * area;
    return isfinite(p) && p > 0.0 ? p : 0.0;
}

// A quad light's power (light_power).
static double quad_light_power(const glint_scene *s, const quad *q) {
    return light_power(&s->materials[q->material], q->area);
}

// Triangle `tri` of mesh instance `ii` in world space, with its power (light_power; 0: not a light).
static double tri_light_make(const glint_scene *s, uint32_t ii, uint32_t tri, tri_light *out) {
    const instance *in = &s->instances[ii];
    const material *m = &s->materials[surface_mesh_material(&s->meshes[in->index], in, tri)];
    if (!material_emits(m)) return 0.0; // most triangles: skip the transform
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

// A world-space sphere light's power (light_power), its area 4 pi r^2.
static double sphere_light_power(const glint_scene *s, const sphere *sp) {
    double r = sp->radius;
    return light_power(&s->materials[sp->material], 4.0 * 3.14159265358979323846 * r * r);
}

// Adds a light of power p to the cdf under construction; its selection probability (the cdf step, so that
// sampling and the MIS weights of BSDF hits agree on it).
static float add_light(light_sampler *pl, light_ref ref, double p, double *sum, double total, size_t count,
                       float *prev) {
    *sum += p;
    size_t k = pl->count++;
    pl->lights[k] = ref;
    pl->cdf[k] = pl->count == count ? 1.0f : (float)(*sum / total);
    float select = pl->cdf[k] - *prev;
    *prev = pl->cdf[k];
    return select;
}

// The light tree's view of a triangle light: which side emits. The side is the shading record's (as
// light_sampler_tri_emitted finds it); where the corners disagree, or the material emits on both, both.
static void tri_light_item(const glint_scene *s, const tri_light *tl, light_tree_item *it) {
    const instance *in = &s->instances[tl->instance];
    const mesh *m = &s->meshes[in->index].geometry;
    static const float corners[3][2] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}};
    int front = 0, back = 0;
    for (int k = 0; k < 3; k++) { // the shading normal is interpolated linearly: its side at the corners decides
        tri_hit th = {0.0f, 1.0f - corners[k][0] - corners[k][1], corners[k][0], corners[k][1]};
        vec3 ng = mat4_apply_normal(&in->xf.inv, mesh_shade(m, tl->tri, &th).ng);
        float side = v3_dot(ng, tl->n);
        front += side > 0.0f;
        back += side < 0.0f;
    }
    bool one_side = !s->materials[tl->material].two_sided && (front == 3 || back == 3);
    it->axis = front == 3 ? tl->n : v3_neg(tl->n);
    it->cos_o = one_side ? 1.0f : -1.0f;
    it->bounds = bounds3_add(bounds3_add(bounds3_add(bounds3_empty(), tl->p0), v3_add(tl->p0, tl->e1)),
                             v3_add(tl->p0, tl->e2));
}

// The light tree over the indexed lights, and the maps from scene quads and spheres to their entries; false when
// out of memory.
static bool build_tree(light_sampler *pl, const glint_scene *s) {
    light_tree_item *items = malloc(pl->count * sizeof *items);
    pl->quad_light = calloc(s->quad_count ? s->quad_count : 1, sizeof *pl->quad_light);
    pl->sphere_light = calloc(s->sphere_count ? s->sphere_count : 1, sizeof *pl->sphere_light);
    bool ok = items && pl->quad_light && pl->sphere_light;
    for (size_t i = 0; ok && i < pl->count; i++) {
        light_ref ref = pl->lights[i];
        light_tree_item *it = &items[i];
        it->cos_e = 0.0f; // flat emitters and spheres: cosine-weighted, over a hemisphere about each normal
        double power;
        if (ref.kind == LIGHT_REF_QUAD) {
            const quad *q = &s->quads[ref.index];
            it->bounds = bounds3_add(bounds3_add(bounds3_add(bounds3_add(bounds3_empty(), q->q), v3_add(q->q, q->u)),
                                                 v3_add(q->q, q->v)), v3_add(q->q, v3_add(q->u, q->v)));
            it->axis = q->normal;
            it->cos_o = s->materials[q->material].two_sided ? -1.0f : 1.0f;
            power = quad_light_power(s, q);
            pl->quad_light[ref.index] = (uint32_t)i;
        } else if (ref.kind == LIGHT_REF_TRIANGLE) {
            const tri_light *tl = &pl->tris[ref.index];
            tri_light_item(s, tl, it);
            power = light_power(&s->materials[tl->material], tl->area);
        } else {
            const sphere *sp = &s->spheres[ref.index];
            vec3 r = v3s(fabsf(sp->radius));
            it->bounds = (bounds3){v3_sub(sp->center, r), v3_add(sp->center, r)};
            it->axis = v3(0.0f, 0.0f, 1.0f);
            it->cos_o = -1.0f;
            power = sphere_light_power(s, sp);
            pl->sphere_light[ref.index] = (uint32_t)i;
        }
        it->power = (float)power;
    }
    ok = ok && light_tree_build(&pl->tree, items, pl->count);
    free(items);
    return ok;
}

bool light_sampler_build(light_sampler *pl, const glint_scene *s, bool tree) {
    memset(pl, 0, sizeof *pl);
    size_t count = 0, tri_count = 0, tri_slots = 0;
    double total = 0.0;
    for (size_t i = 0; i < s->quad_count; i++) {
        double p = quad_light_power(s, &s->quads[i]);
        count += p > 0.0;
        total += p;
    }
    for (size_t i = 0; i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        if (in->kind != INSTANCE_MESH || in->motion) continue; // moving meshes: found by BSDF rays only
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
    size_t sphere_lights = 0;
    for (size_t i = 0; i < s->sphere_count; i++) {
        double p = sphere_light_power(s, &s->spheres[i]);
        sphere_lights += p > 0.0;
        total += p;
    }
    count += sphere_lights;
    if (count == 0 || !isfinite(total)) return true; // nothing to sample: BSDF sampling alone
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
    if (ok && sphere_lights) {
        pl->sphere_select_pdf = calloc(s->sphere_count, sizeof *pl->sphere_select_pdf);
        ok = pl->sphere_select_pdf != NULL;
    }
    if (!ok) {
        light_sampler_release(pl);
        return false;
    }
    double sum = 0.0;
    float prev = 0.0f;
    for (size_t i = 0; i < s->quad_count; i++) {
        double p = quad_light_power(s, &s->quads[i]);
        if (!(p > 0.0)) continue;
        pl->select_pdf[i] = add_light(pl, (light_ref){LIGHT_REF_QUAD, (uint32_t)i}, p, &sum, total, count, &prev);
    }
    pl->quad_count = s->quad_count;
    pl->quad_lights = pl->count;
    size_t slot = 0;
    for (size_t i = 0; tri_count && i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        pl->tri_base[i] = SIZE_MAX;
        if (in->kind != INSTANCE_MESH || in->motion) continue; // moving meshes: found by BSDF rays only
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
            pl->tri_select_pdf[pl->tri_base[i] + t] =
                add_light(pl, (light_ref){LIGHT_REF_TRIANGLE, k}, p, &sum, total, count, &prev);
        }
    }
    if (tri_count) pl->instance_count = s->instance_count;
    for (size_t i = 0; sphere_lights && i < s->sphere_count; i++) {
        double p = sphere_light_power(s, &s->spheres[i]);
        if (!(p > 0.0)) continue;
        pl->sphere_select_pdf[i] =
            add_light(pl, (light_ref){LIGHT_REF_SPHERE, (uint32_t)i}, p, &sum, total, count, &prev);
    }
    if (sphere_lights) pl->sphere_count = s->sphere_count;
    if (tree && pl->count >= LIGHT_TREE_MIN_LIGHTS && !build_tree(pl, s)) {
        light_sampler_release(pl);
        return false;
    }
    return true;
}

size_t light_sampler_choose(const light_sampler *pl, vec3 p, float xi, float *select) {
    if (pl->tree.node_count) return light_tree_sample(&pl->tree, p, xi, select);
    size_t lo = 0, hi = pl->count - 1; // the first light whose cdf exceeds xi
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (xi < pl->cdf[mid]) hi = mid;
        else lo = mid + 1;
    }
    *select = pl->cdf[lo] - (lo ? pl->cdf[lo - 1] : 0.0f); // as light_sampler_build recorded it
    return lo;
}

// The cone a sphere subtends from a point at squared distance d2 from its centre: 1 - cos(theta_max), in the
// form that keeps its precision for small spheres far away, (r^2 / d^2) / (1 + cos(theta_max)); 0 when the
// point is not outside the sphere.
static double sphere_cone_gap(double r2, double d2) {
    if (!(d2 > r2) || !isfinite(d2)) return 0.0;
    double s2 = r2 / d2; // sin^2(theta_max)
    return s2 / (1.0 + sqrt(1.0 - s2));
}

static const double two_pi = 6.28318530717958647692;

float light_sphere_pdf(const sphere *sp, vec3 p) {
    vec3 to = v3_sub(sp->center, p);
    double r = sp->radius, gap = sphere_cone_gap(r * r, (double)v3_len2(to));
    return gap > 0.0 ? (float)(1.0 / (two_pi * gap)) : 0.0f;
}

float light_sphere_pdf_towards(const sphere *sp, vec3 p, vec3 wi) {
    vec3 to = v3_sub(sp->center, p);
    double r = sp->radius, d2 = (double)v3_len2(to), along = (double)v3_dot(wi, to);
    // Inside the cone: cos(angle to the centre)^2 >= cos(theta_max)^2 = 1 - r^2 / d^2, on the near side.
    if (!(along > 0.0) || along * along < d2 - r * r) return 0.0f;
    return light_sphere_pdf(sp, p);
}

bool light_sphere_sample(const sphere *sp, vec3 p, float a, float b, vec3 *wi, float *dist, float *pdf) {
    vec3 to = v3_sub(sp->center, p);
    double r = sp->radius, d2 = (double)v3_len2(to), gap = sphere_cone_gap(r * r, d2);
    if (!(gap > 0.0)) return false;
    // cos(theta) = 1 - b gap, uniform in [cos(theta_max), 1]; sin^2 from (1 - cos)(1 + cos) keeps small angles exact.
    double one_minus_cos = (double)b * gap, cos_t = 1.0 - one_minus_cos;
    double sin_t = sqrt(fmax(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    double phi = two_pi * (double)a, d = sqrt(d2);
    vec3 w = v3_scale(to, (float)(1.0 / d)), t, bt;
    v3_basis(w, &t, &bt);
    vec3 dir = v3_add(v3_scale(w, (float)cos_t),
                      v3_add(v3_scale(t, (float)(sin_t * cos(phi))), v3_scale(bt, (float)(sin_t * sin(phi)))));
    *wi = v3_unit(dir);
    // The nearer root of |p + s wi - c| = r: s = d cos - sqrt(r^2 - d^2 sin^2), >= 0 inside the cone.
    *dist = (float)(d * cos_t - sqrt(fmax(0.0, r * r - d2 * sin_t * sin_t)));
    *pdf = (float)(1.0 / (two_pi * gap));
    return *dist > 0.0f && isfinite(*dist) && isfinite(*pdf);
}

// Probability density, per unit solid angle, with which next-event estimation would have chosen the point
// where a ray of unit direction d hit an emissive quad or mesh triangle at distance t; 0 when it is not an
// indexed light.
float light_sampler_pdf(const light_sampler *pl, const glint_scene *s, const surface *sf, vec3 o, vec3 d, float t) {
    if (sf->kind == HIT_SPHERE) {
        if (sf->instance != HIT_NO_INSTANCE || sf->prim >= pl->sphere_count) return 0.0f;
        float select = pl->sphere_select_pdf[sf->prim];
        if (select > 0.0f && pl->tree.node_count) select = light_tree_pmf(&pl->tree, o, pl->sphere_light[sf->prim]);
        return select > 0.0f ? select * light_sphere_pdf(&s->spheres[sf->prim], o) : 0.0f;
    }
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
        // Triangles come after the quads among the lights, in the same order as tris.
        if (pl->tree.node_count && !((select = light_tree_pmf(&pl->tree, o, pl->quad_lights + lo)) > 0.0f)) return 0.0f;
        float cos_l = fabsf(v3_dot(d, tl->n));
        if (!(cos_l > 0.0f)) return 0.0f;
        return select * t * t / (cos_l * tl->area);
    }
    if (sf->kind != HIT_QUAD || sf->instance != HIT_NO_INSTANCE || sf->prim >= pl->quad_count) return 0.0f;
    float select = pl->select_pdf[sf->prim];
    if (select > 0.0f && pl->tree.node_count) select = light_tree_pmf(&pl->tree, o, pl->quad_light[sf->prim]);
    if (!(select > 0.0f)) return 0.0f;
    const quad *q = &s->quads[sf->prim];
    float cos_l = fabsf(v3_dot(d, q->normal));
    if (!(cos_l > 0.0f)) return 0.0f;
    return select * t * t / (cos_l * q->area);
}

// The emitted radiance of triangle light tl at barycentrics (b1, b2), point x, towards unit direction wi
// (from the receiver to the light): the side and texture coordinates as surface_at gives them to a
// ray that hits it there, so that both strategies see the same emission.
vec3 light_sampler_tri_emitted(const glint_scene *s, const tri_light *tl, float b1, float b2, vec3 x, vec3 wi) {
    const instance *in = &s->instances[tl->instance];
    tri_hit th = {0.0f, 1.0f - b1 - b2, b1, b2};
    mesh_shading sh = mesh_shade(&s->meshes[in->index].geometry, tl->tri, &th);
    vec3 ng = mat4_apply_normal(&in->xf.inv, sh.ng);
    bool front = v3_dot(wi, ng) < 0.0f;
    const material *m = &s->materials[tl->material];
    if (alpha_cut_at(m, s->textures, sh.u, sh.v)) return v3s(0.0f); // a cut part emits nothing, as paths see it
    return mat_emitted(m, s->textures, front, sh.u, sh.v, x);
}
