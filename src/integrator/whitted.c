// whitted.c — the paper's Whitted ray tracer (exact, in double) and its colour-correct variant.
#include "integrator/whitted.h"
#include "integrator/alpha_mask.h"
#include "integrator/sample_scheduler.h"
#include "integrator/spawn.h"
#include "material/bsdf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

// The paper mode must round exactly as the OCaml program does: no fused multiply-adds. GCC does not
// contract in ISO C mode (-std=c17); clang contracts within expressions unless told not to.
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

// ---------------------------------------------------------------------------------------------------
// Paper mode: what the paper's OCaml program computes, operation for operation.
// The program knows spheres only: paper mode sees the scene's world-space spheres and ignores quads,
// meshes, instances and textures (its colours are the materials' constant ones).
// ---------------------------------------------------------------------------------------------------

// Film point of a sample: the pixel centre for a single sample (the paper's one ray a pixel), else uniformly
// jittered in the pixel.
static void whitted_film_point(const glint_scene *s, int x, int y, rng *r, float *fx, float *fy) {
    if (s->settings.spp == 1) {
        *fx = (float)x + 0.5f;
        *fy = (float)y + 0.5f;
        return;
    }
    *fx = (float)x + rng_float(r);
    *fy = (float)y + rng_float(r);
}

/// A point or vector in double, as the program's `point` record.
typedef struct dvec {
    double x, y, z;
} dvec;

enum { PAPER_CHAIN = 64 }; // reflection levels kept on the stack before paper_trace recurses

static dvec dv(double x, double y, double z) { return (dvec){x, y, z}; }
static dvec dv_add(dvec a, dvec b) { return dv(a.x + b.x, a.y + b.y, a.z + b.z); }
static dvec dv_sub(dvec a, dvec b) { return dv(a.x - b.x, a.y - b.y, a.z - b.z); }
static dvec dv_scale(double k, dvec a) { return dv(k * a.x, k * a.y, k * a.z); }
static double dv_dot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double dv_norm(dvec a) { return sqrt(dv_dot(a, a)); }
/// The program's reflected_ray: 2 (l . ncap) ncap - l.
static dvec dv_reflect(dvec ncap, dvec l) { return dv_sub(dv_scale(2.0 * dv_dot(l, ncap), ncap), l); }

// Scene numbers are stored as float, but the program's constants are decimals in double: recover the
// decimal with at most 9 places that rounds to f (0.2f gives the double 0.2, not 0.2000000030), so the
// paper's 0.2, 0.6 and 0.01 are exactly the program's. Integers (every position in the paper) are exact.
static double paper_number(float f) {
    double x = f;
    if (!isfinite(x) || x == nearbyint(x)) return x;
    double scale = 1.0;
    for (int places = 1; places <= 9; places++) {
        scale *= 10.0;
        double d = nearbyint(x * scale) / scale;
        if ((float)d == f) return d;
    }
    return x;
}

static dvec paper_vec(vec3 v) { return dv(paper_number(v.x), paper_number(v.y), paper_number(v.z)); }

// The program's colours are integers 0..255; colour 1.0 in the scene is 255. Snap to the integer when the
// float is within 0.001 of one (200/255 in a scene file gives 200), else keep albedo * 255.
static double paper_colour(float albedo) {
    double c = (double)albedo * 255.0;
    double i = nearbyint(c);
    return fabs(c - i) < 1e-3 ? i : c;
}

// The program's quadratic for the ray o + t d and sphere sp: false when the discriminant is negative (or NaN),
// else its two roots, the + root in *t1.
static bool paper_roots(const sphere *sp, dvec o, dvec d, double *t1, double *t2) {
    double radius = paper_number(sp->radius);
    dvec co = dv_sub(o, paper_vec(sp->center));
    double a = dv_dot(d, d);
    double b = 2.0 * dv_dot(d, co);
    double c = dv_dot(co, co) - radius * radius;
    double disc = b * b - 4.0 * a * c;
    if (!(disc >= 0.0)) return false;
    *t1 = (-b + sqrt(disc)) / (2.0 * a);
    *t2 = (-b - sqrt(disc)) / (2.0 * a);
    return true;
}

// Closest sphere with a root t, tmin <= t <= tmax, brute force in list order; all comparisons inclusive,
// so on a tie the later root and the later sphere win. -1 when there is none.
static long paper_closest(const glint_scene *s, dvec o, dvec d, double tmin, double tmax, double *t_out) {
    long best = -1;
    double best_t = INFINITY;
    for (size_t k = 0; k < s->sphere_count; k++) {
        double t1, t2;
        if (!paper_roots(&s->spheres[k], o, d, &t1, &t2)) continue;
        if (t1 >= tmin && t1 <= tmax && t1 <= best_t) { best_t = t1; best = (long)k; }
        if (t2 >= tmin && t2 <= tmax && t2 <= best_t) { best_t = t2; best = (long)k; }
    }
    *t_out = best_t;
    return best;
}

// Whether any sphere (the one being shaded included) has a root in [tmin, tmax]: the program's shadow test.
static bool paper_blocked(const glint_scene *s, dvec o, dvec d, double tmin, double tmax) {
    for (size_t k = 0; k < s->sphere_count; k++) {
        double t1, t2;
        if (!paper_roots(&s->spheres[k], o, d, &t1, &t2)) continue;
        if ((t1 >= tmin && t1 <= tmax) || (t2 >= tmin && t2 <= tmax)) return true;
    }
    return false;
}

// The program's til: the intensity at p (normal `normal`, not unit; viewed from o) summed over the lights
// in list order, specular before diffuse. One intensity per colour channel, so that coloured lights work;
// with white lights the three channels are the program's scalar, bit for bit.
static dvec paper_lighting(const glint_scene *s, dvec normal, dvec p, dvec o, int shininess, thread_stats *ts) {
    dvec total = dv(0.0, 0.0, 0.0);
    for (size_t k = 0; k < s->light_count; k++) {
        const light *li = &s->lights[k];
        dvec i = paper_vec(li->intensity);
        dvec c = dv(0.0, 0.0, 0.0);
        if (li->kind == LIGHT_AMBIENT) {
            c = dv_add(i, c);
        } else {
            dvec l;
            double tmax;
            if (li->kind == LIGHT_POINT || li->kind == LIGHT_SPOT) {
                l = dv_sub(paper_vec(li->position), p);
                tmax = 1.0; // the light itself is at t = 1
                if (li->kind == LIGHT_SPOT) {
                    // Its cone scales it as it would a point light of the same intensity.
                    double len = dv_norm(l);
                    float share = len > 0.0 ? light_spot_falloff(li, v3((float)(l.x / len), (float)(l.y / len), (float)(l.z / len))) : 0.0f;
                    i = dv_scale((double)share, i);
                }
            } else {
                l = paper_vec(li->direction);
                tmax = INFINITY;
            }
            ts->shadow_rays++;
            if (!paper_blocked(s, p, l, 0.0001, tmax)) {
                dvec ncap = dv_scale(1.0 / dv_norm(normal), normal);
                dvec refl = dv_reflect(ncap, l);
                dvec view = dv_sub(o, p);
                double rv = dv_dot(refl, view);
                if (rv > 0.0 && shininess > 0) {
                    double f = pow(rv / (dv_norm(refl) * dv_norm(view)), (double)shininess);
                    c = dv(c.x + i.x * f, c.y + i.y * f, c.z + i.z * f);
                }
                double nl = dv_dot(normal, l);
                if (nl > 0.0) {
                    double den = dv_norm(l) * dv_norm(normal);
                    c = dv(c.x + i.x * nl / den, c.y + i.y * nl / den, c.z + i.z * nl / den);
                }
            }
        }
        total = dv_add(total, c);
    }
    return total;
}

// The program's rtx_inner: intensity along o + t d (t >= tmin) with up to `limit` reflections, and the
// sphere hit first (-1 when the ray escapes; the intensity is then 0), at t = *t_first (when not NULL). The program recurses,
// I = I_local (1 - rfl) + rfl I_reflected; this walks the chain forwards, keeps each level, and folds from
// the deepest level back so that every sum rounds as the recursion's does. Chains longer than PAPER_CHAIN
// continue in a recursive call, so the stack stays small for any depth.
static long paper_trace(const glint_scene *s, dvec o, dvec d, double tmin, int limit, thread_stats *ts,
                        dvec *out, double *t_first) {
    dvec level_i[PAPER_CHAIN];
    double level_rfl[PAPER_CHAIN];
    int n = 0;
    long first = -1;
    dvec value = dv(0.0, 0.0, 0.0); // intensity along the last ray of the chain; 0 when it escapes
    for (;;) {
        ts->rays++;
        double t;
        long k = paper_closest(s, o, d, tmin, INFINITY, &t);
        if (k < 0) break;
        if (n == 0) {
            first = k;
            if (t_first) *t_first = t;
        }
        const sphere *sp = &s->spheres[k];
        const material *m = &s->materials[sp->material];
        bool phong = m->kind == MAT_PHONG;
        dvec p = dv_add(o, dv_scale(t, d));
        dvec normal = dv_sub(p, paper_vec(sp->center));
        if (sp->radius < 0.0f) normal = dv_scale(-1.0, normal); // a negative radius turns the normal inward
        dvec local = paper_lighting(s, normal, p, o, phong ? m->specular : 0, ts);
        double rfl = phong ? paper_number(m->reflective) : 0.0;
        if (!(rfl > 0.0 && limit > 0)) {
            value = local;
            break;
        }
        level_i[n] = local;
        level_rfl[n] = rfl;
        n++;
        d = dv_reflect(dv_scale(1.0 / dv_norm(normal), normal), dv_scale(-1.0, d));
        o = p;
        tmin = 0.001;
        limit--;
        if (n == PAPER_CHAIN) {
            paper_trace(s, o, d, tmin, limit, ts, &value, NULL);
            break;
        }
    }
    for (int k = n - 1; k >= 0; k--) {
        double rfl = level_rfl[k];
        dvec l = level_i[k];
        value = dv(l.x * (1.0 - rfl) + rfl * value.x, l.y * (1.0 - rfl) + rfl * value.y,
                   l.z * (1.0 - rfl) + rfl * value.z);
    }
    *out = value;
    return first;
}

// The program's myrgb/clamp: colour * I, 255 above 255, 0 below 0, else truncated; returned as the linear
// value that the film's linear transform turns back into exactly that byte.
static float paper_channel(double colour, double intensity) {
    double x = colour * intensity;
    int byte;
    if (x > 255.0) byte = 255;
    else if (x < 0.0 || isnan(x)) byte = 0;
    else byte = (int)x;
    return (float)byte / 255.0f;
}

// The albedo AOV of material m of albedo `albedo` at a Whitted integrator's first hit: an emitter's normalised
// emission, any other material's albedo (a mirror's and glass's tint: the Whitted integrators do not look past
// them), clamped to [0, 1].
static vec3 whitted_aov_albedo(const material *m, vec3 albedo, vec3 emitted) {
    return m->kind == MAT_DIFFUSE_LIGHT ? integrator_aov_emitter(emitted) : integrator_aov_albedo(albedo);
}

// The AOVs of the paper mode's first hit: sphere k (-1: none, the white background) at o + t d.
static void paper_aov(const glint_scene *s, long k, dvec o, dvec d, double t, film_aov_sample *aov) {
    aov->normal = v3s(0.0f);
    aov->depth = INFINITY;
    if (k < 0) {
        aov->albedo = v3s(1.0f); // the program's white background
        return;
    }
    const sphere *sp = &s->spheres[k];
    const material *m = &s->materials[sp->material];
    aov->albedo = whitted_aov_albedo(m, m->albedo, m->emission);
    dvec p = dv_add(o, dv_scale(t, d)), q = dv_sub(p, paper_vec(sp->center));
    double len = dv_norm(q);
    if (len > 0.0) {
        // The normal facing the ray, whichever side of the sphere it arrived on.
        double sign = dv_dot(q, d) > 0.0 ? -1.0 : 1.0;
        aov->normal = v3((float)(sign * q.x / len), (float)(sign * q.y / len), (float)(sign * q.z / len));
    }
    aov->depth = (float)(t * dv_norm(d)); // the ray starts at the eye: the distance from the camera
}

static vec3 paper_sample(const integrator *it, int x, int y, rng *r, thread_stats *ts, film_aov_sample *aov) {
    const glint_scene *s = it->scene;
    const camera *c = &it->camera;
    float fx, fy;
    whitted_film_point(s, x, y, r, &fx, &fy);
    dvec o, d;
    double tmin;
    if (c->kind == CAMERA_VIEWPORT) {
        // The program samples pixel (x, y) at canvas point (x - W/2, H/2 - 1 - y), film point (x, y + 1):
        // move the pixel centre there, so one sample is the program's ray and jitter surrounds it.
        double v[3];
        camera_viewport_point(c, (double)fx - 0.5, (double)fy + 0.5, v);
        o = dv(c->position[0], c->position[1], c->position[2]);
        d = dv(v[0], v[1], v[2]); // D = V - O, not normalised; the viewport point is relative to the eye
        tmin = 1.0;               // in front of the viewport
    } else {
        ray cr = camera_ray(c, fx, fy, r);
        o = dv(cr.o.x, cr.o.y, cr.o.z);
        d = dv(cr.d.x, cr.d.y, cr.d.z);
        tmin = 0.0;
    }
    dvec intensity;
    double t_first = 0.0;
    long k = paper_trace(s, o, d, tmin, s->settings.max_depth, ts, &intensity, &t_first);
    if (aov) paper_aov(s, k, o, d, t_first, aov);
    if (k < 0) return v3s(1.0f); // the program's background is white
    vec3 albedo = s->materials[s->spheres[k].material].albedo;
    return v3(paper_channel(paper_colour(albedo.x), intensity.x), paper_channel(paper_colour(albedo.y), intensity.y),
              paper_channel(paper_colour(albedo.z), intensity.z));
}

// ---------------------------------------------------------------------------------------------------
// Colour mode: the Whitted ray tracer of "Computer Graphics from Scratch", with RGB colours and lights,
// glass, and no clamping before output.
// ---------------------------------------------------------------------------------------------------

static const float MIN_WEIGHT = 1e-4f;  // a branch weighing less cannot change an 8-bit pixel
static const uint32_t NO_SPHERE = UINT32_MAX;

/// A ray leaving the surface of world-space sphere `from` (NO_SPHERE for camera rays and rays leaving
/// any other surface).
typedef struct spawned {
    ray r;
    uint32_t from;
} spawned;

/// Whether a hit is on one of the scene's world-space spheres (s->spheres[h->prim]).
static bool hit_world_sphere(const hit *h) { return h->kind == HIT_SPHERE && h->instance == HIT_NO_INSTANCE; }

// The root of sphere sp along r nearest to t, solved again in double: in float, o - centre is only known
// to half an ulp of the centre's coordinates (2.4e-4 for the paper's radius-5000 ground), in double exactly.
static float refine_t(const sphere *sp, const ray *r, float t) {
    double f[3] = {(double)r->o.x - sp->center.x, (double)r->o.y - sp->center.y, (double)r->o.z - sp->center.z};
    double d[3] = {r->d.x, r->d.y, r->d.z};
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double b = -(f[0] * d[0] + f[1] * d[1] + f[2] * d[2]);
    double l2 = 0.0, f2 = 0.0, rr = (double)sp->radius * sp->radius;
    for (int i = 0; i < 3; i++) {
        double l = f[i] + d[i] * (b / a);
        l2 += l * l;
        f2 += f[i] * f[i];
    }
    double disc = fmax(rr - l2, 0.0); // float found a hit: a grazing one at worst
    double q = b + copysign(sqrt(a * disc), b);
    if (q == 0.0) return t;
    double t0 = (f2 - rr) / q, t1 = q / a;
    return (float)(fabs(t0 - t) <= fabs(t1 - t) ? t0 : t1);
}

// Closest hit of a ray. For a ray leaving the surface of sphere `from`, that sphere's float roots near the
// origin are rounding noise (and an offset origin would move shadow edges): its one true root is
// t = -2 (o - C).d / |d|^2, the other being 0, so its float roots are skipped and this one stands in.
// With alpha masks (it->alpha_masks) a hit the mask cuts away does not count: the search goes on past it, as
// alpha_intersect's does, at most ALPHA_MAX_LAYERS times.
static bool color_intersect(const integrator *it, const spawned *sr, hit *h) {
    const glint_scene *s = it->scene;
    ray r = sr->r;
    float t_own = -1.0f;
    if (sr->from != NO_SPHERE) {
        const sphere *own = &s->spheres[sr->from];
        t_own = -2.0f * v3_dot(v3_sub(r.o, own->center), r.d) / v3_len2(r.d);
        if (t_own > r.tmin && t_own < r.tmax) r.tmax = t_own; // nothing beyond it matters
        else t_own = -1.0f;
    }
    int cuts = it->alpha_masks ? 0 : ALPHA_MAX_LAYERS;
    // Each pass steps over at most one float root of `from`, which has two.
    for (int pass = 0; pass < 3;) {
        if (!accel_intersect(it->accel, &r, h)) break;
        float t = h->t;
        if (hit_world_sphere(h)) {
            if (h->prim == sr->from) {
                r.tmin = t;
                pass++;
                continue;
            }
            h->t = refine_t(&s->spheres[h->prim], &r, t);
        } // quads, triangles, instances: offset origins keep them apart
        if (cuts < ALPHA_MAX_LAYERS && alpha_cut(s, &r, h)) {
            r.tmin = t;
            cuts++;
            continue;
        }
        return true;
    }
    if (t_own < 0.0f) return false;
    h->t = t_own;
    h->prim = sr->from;
    h->kind = HIT_SPHERE;
    h->instance = HIT_NO_INSTANCE;
    h->b1 = h->b2 = 0.0f;
    if (cuts < ALPHA_MAX_LAYERS && alpha_cut(s, &r, h)) { // the far side of a masked sphere: on beyond it
        r.tmin = t_own;
        r.tmax = sr->r.tmax;
        return alpha_intersect(it->accel, s, &r, h);
    }
    return true;
}

/// Where the colour mode's secondary rays leave a surface. Rays leaving a world-space sphere start exactly at
/// the hit point and color_intersect stands in for that sphere's roots (precision the golden test needs; an
/// offset of the sphere's error bound, 2^-21 of the paper ground's radius 5000, moves shadow edges);
/// rays leaving anything else start at an origin offset by the surface's error bound (spawn.h). Either way
/// every other surface counts from t > 0, so none is skipped at any scale.
typedef struct color_origin {
    spawn_point sp;
    uint32_t from; ///< the world sphere, or NO_SPHERE
} color_origin;

static color_origin color_origin_of(const glint_scene *s, const surface *sf) {
    color_origin out;
    if (sf->kind == HIT_SPHERE && sf->instance == HIT_NO_INSTANCE) {
        out.from = sf->prim;
        out.sp.p = sf->p;
        out.sp.n = sf->ng;
        out.sp.offset = 0.0f;
        out.sp.time = sf->time;
    } else {
        out.from = NO_SPHERE;
        out.sp = spawn_point_of(s, sf);
    }
    return out;
}

// A secondary ray leaving co along d, counting every hit at t > 0: no fixed minimum distance, which skipped
// real surfaces closer than it (a reflection near a mirror box's edge escaped through the adjacent face).
static spawned spawn(const color_origin *co, vec3 d) {
    spawned out;
    out.r.o = co->from == NO_SPHERE ? spawn_origin(&co->sp, d) : co->sp.p;
    out.r.d = d;
    out.r.tmin = 0.0f;
    out.r.tmax = INFINITY;
    out.r.time = co->sp.time;
    out.from = co->from;
    return out;
}

// Ambient + diffuse lighting times the surface colour, plus Phong highlights times the highlight colour;
// light intensities are RGB. A light counts only when no surface (this one included) lies on the shadow ray
// P + tL, t in (0, 1) towards a point light (L = position - P), (0, inf) along a directional one.
static vec3 color_local(const integrator *it, const material *m, vec3 albedo, const color_origin *co,
                        const surface *sf, vec3 view, thread_stats *ts) {
    const glint_scene *s = it->scene;
    vec3 ambient = v3s(0.0f), diffuse = v3s(0.0f), specular = v3s(0.0f);
    int shininess = m->kind == MAT_PHONG ? m->specular : 0;
    vec3 n = sf->n;
    for (size_t k = 0; k < s->light_count; k++) {
        const light *li = &s->lights[k];
        if (li->kind == LIGHT_AMBIENT) {
            ambient = v3_add(ambient, li->intensity);
            continue;
        }
        const bool placed = li->kind == LIGHT_POINT || li->kind == LIGHT_SPOT;
        vec3 l = placed ? v3_sub(li->position, sf->p) : li->direction;
        vec3 intensity = li->intensity;
        if (li->kind == LIGHT_SPOT) {
            float len = v3_len(l);
            if (!(len > 0.0f)) continue;
            float share = light_spot_falloff(li, v3_scale(l, 1.0f / len));
            if (!(share > 0.0f)) continue;
            intensity = v3_scale(intensity, share);
        }
        float nl = v3_dot(n, l);
        float kd = nl > 0.0f ? nl / v3_len(l) : 0.0f;
        float ks = 0.0f;
        if (shininess > 0) {
            vec3 refl = v3_sub(v3_scale(n, 2.0f * nl), l);
            float rv = v3_dot(refl, view);
            if (rv > 0.0f) ks = powf(rv / (v3_len(refl) * v3_len(view)), (float)shininess);
        }
        if (!(kd > 0.0f) && !(ks > 0.0f)) continue; // nothing to shadow
        spawned sh = spawn(co, l);
        if (placed) sh.r.tmax = 1.0f; // the light itself is at t = 1
        ts->shadow_rays++;
        hit h;
        if (color_intersect(it, &sh, &h)) continue;
        diffuse = v3_add(diffuse, v3_scale(intensity, kd));
        specular = v3_add(specular, v3_scale(intensity, ks));
    }
    vec3 highlight = m->has_specular_color ? m->specular_color : albedo;
    return v3_add(v3_mul(albedo, v3_add(ambient, diffuse)), v3_mul(highlight, specular));
}

// Radiance along r times weight w, with `depth` bounces left, and (aov not NULL) the AOVs of r's first hit,
// its depth measured from r's origin. Mirror chains loop; at a glass surface the lighter of the reflected and
// refracted branches recurses and the heavier loops, so the stack depth stays logarithmic in 1 / MIN_WEIGHT
// whatever the depth budget.
static vec3 color_trace(const integrator *it, spawned r, int depth, vec3 w, thread_stats *ts, film_aov_sample *aov) {
    const glint_scene *s = it->scene;
    vec3 sum = v3s(0.0f);
    if (aov) {
        aov->albedo = aov->normal = v3s(0.0f);
        aov->depth = INFINITY;
    }
    for (;;) {
        if (v3_max_comp(w) < MIN_WEIGHT) return sum;
        ts->rays++;
        hit h;
        vec3 d = v3_unit(r.r.d);
        if (!color_intersect(it, &r, &h)) {
            vec3 bg = scene_background(s, d);
            if (aov) aov->albedo = integrator_aov_albedo(bg); // the background is the albedo; no normal
            return v3_add(sum, v3_mul(w, bg));
        }
        surface sf = surface_at(s, &r.r, &h);
        const material *m = &s->materials[sf.material];
        if (m->kind == MAT_DIFFUSE_LIGHT) {
            vec3 tp = surface_texture_point(s, &sf, m->emission_texture);
            vec3 le = mat_emitted(m, s->textures, sf.front, sf.u, sf.v, tp);
            if (aov) {
                aov->albedo = integrator_aov_emitter(le);
                aov->normal = sf.n;
                aov->depth = h.t * v3_len(r.r.d);
            }
            return v3_add(sum, v3_mul(w, le));
        }
        vec3 albedo = mat_albedo(m, s->textures, sf.u, sf.v, surface_texture_point(s, &sf, m->albedo_texture));
        if (aov) { // the first hit: recorded once, never by the reflected and refracted rays
            aov->albedo = whitted_aov_albedo(m, albedo, v3s(0.0f));
            aov->normal = sf.n;
            aov->depth = h.t * v3_len(r.r.d);
            aov = NULL;
        }
        color_origin co = color_origin_of(s, &sf);
        switch (m->kind) {
        case MAT_DIFFUSE_LIGHT: return sum; // handled above
        case MAT_CONDUCTOR:
        case MAT_PBR: {
            // The microfacet materials as Whitted sees them (bsdf_whitted_view): a diffuse base lit by the
            // lights (pbr), pbr's emission, and a mirror weighted by the Fresnel reflectance; roughness ignored.
            vec3 tp = surface_texture_point(s, &sf, 0);
            bsdf_site site = {sf.n, v3s(0.0f), v3s(0.0f), sf.u, sf.v, tp, sf.front};
            bsdf b;
            bsdf_init(&b, m, s->textures, albedo, &site);
            bsdf_whitted view = bsdf_whitted_view(&b, -v3_dot(d, b.n));
            vec3 local = mat_emitted(m, s->textures, sf.front, sf.u, sf.v, surface_texture_point(s, &sf, m->emission_texture));
            if (v3_max_comp(view.diffuse) > 0.0f)
                local = v3_add(local, color_local(it, m, view.diffuse, &co, &sf, v3_neg(d), ts));
            sum = v3_add(sum, v3_mul(w, local));
            if (!(v3_max_comp(view.mirror) > 0.0f) || depth <= 0) return sum;
            w = v3_mul(w, view.mirror);
            r = spawn(&co, v3_reflect(d, b.n));
            depth--;
            continue;
        }
        case MAT_KIND_COUNT:
        case MAT_LAMBERTIAN:
        case MAT_PHONG: {
            vec3 local = color_local(it, m, albedo, &co, &sf, v3_neg(d), ts);
            float rfl = m->kind == MAT_PHONG ? m->reflective : 0.0f;
            if (!(rfl > 0.0f) || depth <= 0) return v3_add(sum, v3_mul(w, local));
            // local (1 - rfl) + rfl (what the reflected ray sees)
            sum = v3_add(sum, v3_mul(w, v3_scale(local, 1.0f - rfl)));
            w = v3_scale(w, rfl);
            r = spawn(&co, v3_reflect(d, sf.n));
            depth--;
            continue;
        }
        case MAT_METAL:
            // A perfect mirror tinted by its albedo; fuzz belongs to the path tracer.
            if (depth <= 0) return sum;
            w = v3_mul(w, albedo);
            r = spawn(&co, v3_reflect(d, sf.n));
            depth--;
            continue;
        case MAT_DIELECTRIC:
        case MAT_ROUGH_DIELECTRIC: { // rough glass is smooth glass here: Whitted traces no glossy lobes
            if (depth <= 0) return sum;
            depth--;
            float eta = sf.front ? 1.0f / m->ior : m->ior;
            float cos_i = fminf(-v3_dot(d, sf.n), 1.0f);
            float sin2_t = eta * eta * (1.0f - cos_i * cos_i);
            spawned reflected = spawn(&co, v3_reflect(d, sf.n));
            if (sin2_t > 1.0f) { // total internal reflection
                r = reflected;
                continue;
            }
            // Schlick with the cosine on the less dense side (the transmitted one when leaving glass).
            float cos_t = sqrtf(1.0f - sin2_t);
            float fresnel = schlick_reflectance(eta <= 1.0f ? cos_i : cos_t, eta);
            spawned refracted = spawn(&co, v3_refract(d, sf.n, eta));
            vec3 w_refl = v3_scale(w, fresnel);
            vec3 w_refr = v3_mul(w, v3_scale(albedo, 1.0f - fresnel));
            if (v3_max_comp(w_refl) < v3_max_comp(w_refr)) {
                sum = v3_add(sum, color_trace(it, reflected, depth, w_refl, ts, NULL));
                r = refracted;
                w = w_refr;
            } else {
                sum = v3_add(sum, color_trace(it, refracted, depth, w_refr, ts, NULL));
                r = reflected;
                w = w_refl;
            }
            continue;
        }
        }
        return sum;
    }
}

// Primary ray of a colour-mode sample, and how far its origin lies from the camera (*from_eye). The viewport
// camera maps pixels as the paper does (pixel (x, y) is centred on film point (x, y + 1)), computed in double,
// and its rays start on the viewport; the look-at camera is the camera module's, its rays start at the camera.
static ray color_primary_ray(const integrator *it, int x, int y, rng *r, float *from_eye) {
    const glint_scene *s = it->scene;
    const camera *c = &it->camera;
    float fx, fy;
    whitted_film_point(s, x, y, r, &fx, &fy);
    *from_eye = 0.0f;
    if (c->kind != CAMERA_VIEWPORT) return camera_ray(c, fx, fy, r);
    double v[3];
    camera_viewport_point(c, (double)fx - 0.5, (double)fy + 0.5, v);
    *from_eye = (float)sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    ray out;
    out.o = v3((float)(c->position[0] + v[0]), (float)(c->position[1] + v[1]), (float)(c->position[2] + v[2]));
    out.d = v3_unit(v3((float)v[0], (float)v[1], (float)v[2]));
    out.tmin = 0.0f; // the ray starts on the viewport plane: t >= 1 in the paper's parametrisation
    out.tmax = INFINITY;
    out.time = c->shutter_open; // the Whitted integrators see the scene as it is when the shutter opens
    return out;
}

// One sample of pixel (x, y); r is already seeded for exactly this sample.
static vec3 whitted_sample(const integrator *it, int x, int y, uint32_t sample, rng *r, thread_stats *ts,
                           film_aov_sample *aov) {
    (void)sample;
    const glint_scene *s = it->scene;
    if (s->settings.whitted_mode == WHITTED_PAPER) return paper_sample(it, x, y, r, ts, aov);
    float from_eye;
    spawned primary = {color_primary_ray(it, x, y, r, &from_eye), NO_SPHERE};
    vec3 c = color_trace(it, primary, s->settings.max_depth, v3s(1.0f), ts, aov);
    if (aov) aov->depth += from_eye; // from the camera, not from the viewport
    return c;
}

// A tile pass, sample by sample.
static bool whitted_render_tile(const integrator *it, const tile_pass *tp, film_tile *ft, thread_stats *ts) {
    return scheduler_tile_by_samples(it, tp, ft, ts, whitted_sample);
}

integrator *whitted_create(const glint_scene *s, const accel *a, glint_error *err) {
    integrator *it = malloc(sizeof *it);
    if (!it) {
        snprintf(err->message, sizeof err->message, "out of memory preparing the Whitted integrator");
        return NULL;
    }
    integrator_init(it, s, a);
    it->sample = whitted_sample;
    it->render_tile = whitted_render_tile;
    it->release = NULL;
    return it;
}
