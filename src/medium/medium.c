// medium.c — where a ray lies inside a medium's boundary, the transmittance of the media along a segment, and
// the free-flight sampling of a path through them (spectral MIS over the three channels).
#include "medium/medium.h"

#include <math.h>

// M p (w = 1 for a point, 0 for a direction) in double, from the float matrix.
static void apply_double(const mat4 *a, const double p[3], double w, double out[3]) {
    for (int i = 0; i < 3; i++)
        out[i] = (double)a->m[i][0] * p[0] + (double)a->m[i][1] * p[1] + (double)a->m[i][2] * p[2] + (double)a->m[i][3] * w;
}

// The two roots of |o + t d - c|^2 = r^2, from the distance of the line to the centre (Haines et al.'s form:
// no cancellation for a ray far from a big sphere); false when the line misses.
static bool line_sphere(const double o[3], const double d[3], const double c[3], double r, double *t0, double *t1) {
    double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
    // A unit direction in float has |a - 1| < 1e-6: dividing by a would move the roots by less than the float
    // they become, so the path's free flights skip the three divisions (a chain with the square root).
    bool unit = fabs(a - 1.0) < 1e-6;
    double ba = unit ? b : b / a;
    double l2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double l = oc[k] - ba * d[k]; // the line's closest point to the centre, relative to it
        l2 += l * l;
    }
    double disc = r * r - l2;
    if (!(disc >= 0.0) || !(a > 0.0)) return false;
    if (unit) {
        double h = sqrt(disc);
        *t0 = -b - h;
        *t1 = -b + h;
        return true;
    }
    double h = sqrt(a * disc);
    *t0 = (-b - h) / a;
    *t1 = (-b + h) / a;
    return true;
}

// The slab test: where the line o + t d is inside [lo, hi] on every axis; false when nowhere.
static bool line_box(const double o[3], const double d[3], const double lo[3], const double hi[3], double *t0, double *t1) {
    double a = -INFINITY, b = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0) { // parallel to the slab: inside it everywhere or nowhere
            if (o[k] < lo[k] || o[k] > hi[k]) return false;
            continue;
        }
        double inv = 1.0 / d[k];
        double ta = (lo[k] - o[k]) * inv, tb = (hi[k] - o[k]) * inv;
        if (ta > tb) {
            double x = ta;
            ta = tb;
            tb = x;
        }
        a = ta > a ? ta : a;
        b = tb < b ? tb : b;
    }
    if (!(a <= b)) return false;
    *t0 = a;
    *t1 = b;
    return true;
}

// The part of a ray inside a medium's boundary: (t0, t1) where `inside`. By value: the loops over media keep it in
// registers, where through pointers it went by the stack (the out-of-line path takes their address).
typedef struct span {
    float t0, t1;
    bool inside;
} span;

// medium_segment for a sphere in world space (book 2's media), in scalars and inlined where the media are
// looped over: line_sphere's arithmetic operation for operation (the same roots, the same clipping, hence the
// same bytes) without the arrays that path copies through memory (book 2's final scene 1.034x).
static inline span world_sphere_span(const medium *m, vec3 o, vec3 d, float tmin, float tmax) {
    double ox = (double)o.x - (double)m->center.x, oy = (double)o.y - (double)m->center.y,
           oz = (double)o.z - (double)m->center.z, dx = d.x, dy = d.y, dz = d.z;
    double a = dx * dx + dy * dy + dz * dz;
    double b = ox * dx + oy * dy + oz * dz;
    bool unit = fabs(a - 1.0) < 1e-6;
    double ba = unit ? b : b / a;
    double lx = ox - ba * dx, ly = oy - ba * dy, lz = oz - ba * dz;
    double l2 = lx * lx;
    l2 += ly * ly;
    l2 += lz * lz;
    double r = m->radius, disc = r * r - l2;
    if (!(disc >= 0.0) || !(a > 0.0)) return (span){0.0f, 0.0f, false};
    double h = unit ? sqrt(disc) : sqrt(a * disc);
    double near = unit ? -b - h : (-b - h) / a, far = unit ? -b + h : (-b + h) / a;
    if (near < (double)tmin) near = tmin;
    if (far > (double)tmax) far = tmax;
    if (!(near < far)) return (span){0.0f, 0.0f, false};
    float f0 = (float)near, f1 = (float)far;
    return (span){f0, f1, f0 < f1};
}

// medium_segment for the other boundaries (transformed spheres, boxes), through object space.
static span object_span(const medium *m, vec3 o, vec3 d, float tmin, float tmax) {
    double wo[3] = {o.x, o.y, o.z}, wd[3] = {d.x, d.y, d.z}, oo[3], od[3];
    // An affine map keeps the parameter t of every point of the line: the interval is the object space one.
    if (m->transformed) {
        apply_double(&m->to_object, wo, 1.0, oo);
        apply_double(&m->to_object, wd, 0.0, od);
    } else {
        for (int k = 0; k < 3; k++) oo[k] = wo[k], od[k] = wd[k];
    }
    double a, b;
    if (m->shape == MEDIUM_SPHERE) {
        double c[3] = {m->center.x, m->center.y, m->center.z};
        if (!line_sphere(oo, od, c, m->radius, &a, &b)) return (span){0.0f, 0.0f, false};
    } else {
        double lo[3] = {m->lo.x, m->lo.y, m->lo.z}, hi[3] = {m->hi.x, m->hi.y, m->hi.z};
        if (!line_box(oo, od, lo, hi, &a, &b)) return (span){0.0f, 0.0f, false};
    }
    if (a < (double)tmin) a = tmin;
    if (b > (double)tmax) b = tmax;
    if (!(a < b)) return (span){0.0f, 0.0f, false};
    float f0 = (float)a, f1 = (float)b;
    return (span){f0, f1, f0 < f1};
}

// medium_segment's span, inlined in the loops over media.
static inline span span_of(const medium *m, vec3 o, vec3 d, float tmin, float tmax) {
    if (m->shape == MEDIUM_SPHERE && !m->transformed) return world_sphere_span(m, o, d, tmin, tmax);
    return object_span(m, o, d, tmin, tmax);
}

bool medium_segment(const medium *m, vec3 o, vec3 d, float tmin, float tmax, float *t0, float *t1) {
    span sp = span_of(m, o, d, tmin, tmax);
    *t0 = sp.t0;
    *t1 = sp.t1;
    return sp.inside;
}

// exp(-tau) per channel (one exp where the channels are equal: grey media).
static vec3 exp_neg(const double tau[3]) {
    if (tau[0] == tau[1] && tau[1] == tau[2]) return v3s((float)exp(-tau[0]));
    return v3((float)exp(-tau[0]), (float)exp(-tau[1]), (float)exp(-tau[2]));
}

// Adds to tau each medium's sigma_t times the length of o + t d (length |d| per unit t) inside it, tmin < t < tmax.
static void optical_depth(const medium *media, size_t count, vec3 o, vec3 d, float tmin, float tmax, double tau[3]) {
    double len = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
    for (size_t i = 0; i < count; i++) {
        span sp = span_of(&media[i], o, d, tmin, tmax);
        if (!sp.inside) continue;
        double l = ((double)sp.t1 - (double)sp.t0) * len;
        tau[0] += media[i].sigma_t.x * l;
        tau[1] += media[i].sigma_t.y * l;
        tau[2] += media[i].sigma_t.z * l;
    }
}

vec3 medium_transmittance(const medium *media, size_t count, vec3 o, vec3 d, float tmin, float tmax) {
    double tau[3] = {0.0, 0.0, 0.0};
    optical_depth(media, count, o, d, tmin, tmax, tau);
    return exp_neg(tau);
}

// (a + b + c) / 3 of a vector's channels.
static float mean3(vec3 v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }

medium_event medium_sample(const medium *media, size_t count, const texture *textures, vec3 o, vec3 d, float tmax,
                           medium_path *mp, rng *r) {
    medium_event ev = {false, 0, tmax, o, v3s(1.0f)};
    float first = tmax;
    bool crossed = false, media_grey = true; // media_grey: every medium crossed has equal densities in R, G, B
    // Each medium's events along its segment form a Poisson process of rate sigma_t (in the path's channel),
    // independent of the others': the earliest of their first events is the first event of their sum, and it
    // falls in medium i with probability sigma_t,i / sum, as it must.
    for (size_t i = 0; i < count; i++) {
        span sp = span_of(&media[i], o, d, 0.0f, tmax);
        if (!sp.inside) continue;
        crossed = true;
        vec3 st = media[i].sigma_t;
        media_grey = media_grey && st.x == st.y && st.y == st.z;
        if (mp->hero < 0) { // the path's channel, uniform, drawn once
            int c = (int)(rng_float(r) * 3.0f);
            mp->hero = c > 2 ? 2 : c;
        }
        float u = rng_float(r);
        double rate = v3_comp(media[i].sigma_t, mp->hero);
        if (!(rate > 0.0)) continue;
        // -ln(1 - u): 1 - u is exact in float (u has 24 bits) and positive, and float's logarithm is the cheaper
        double t = (double)sp.t0 - (double)logf(1.0f - u) / rate;
        if (t < (double)sp.t1 && t < (double)first) {
            first = (float)t;
            ev.scattered = true;
            ev.index = (uint32_t)i;
        }
    }
    if (!crossed) return ev;
    // Grey media on a path that has met only grey ones (book 2's): the optical depth's channels are equal, so the
    // transmittance cancels below and is not computed (its three exp were 40 % of book 2's final scene).
    vec3 ra = mp->ratio;
    bool ratio_grey = ra.x == ra.y && ra.y == ra.z;
    double tau[3] = {0.0, 0.0, 0.0};
    vec3 tr = v3s(1.0f);
    if (!(media_grey && ratio_grey)) {
        optical_depth(media, count, o, d, 0.0f, first, tau);
        tr = exp_neg(tau);
    }
    const medium *m = ev.scattered ? &media[ev.index] : NULL;
    vec3 sigma_s = v3s(0.0f);
    if (m) {
        ev.t = first;
        ev.p = v3_fma(o, d, first);
        sigma_s = m->albedo_texture >= 0 ? v3_mul(m->sigma_t, texture_value(&textures[m->albedo_texture], 0.0f, 0.0f, ev.p))
                                         : m->sigma_s;
    }
    // Then the factors are exactly 1 and the albedo, without the rounding of tr / tr. (Grey media give equal
    // channels of tau, computed alike; non-grey ones may too, where their segment lies beyond the event.)
    bool grey = ratio_grey && ((media_grey) || (tau[0] == tau[1] && tau[1] == tau[2]));
    if (grey && !m) return ev;
    if (grey && m->sigma_t.x == m->sigma_t.y && m->sigma_t.y == m->sigma_t.z) {
        float st = m->sigma_t.x; // divided, not scaled by 1 / st: an albedo of 1 stays exactly 1
        ev.weight = v3(sigma_s.x / st, sigma_s.y / st, sigma_s.z / st);
        return ev;
    }
    // The outcome's contribution f and its density q per channel: passing, f = q = tr; scattering at t in m,
    // f = tr sigma_s and q = tr sigma_t. The path's weight is its f over the mean of its densities in the three
    // channels: the factor f mean(ratio) / mean(ratio q), and the ratios become ratio q (rescaled).
    vec3 f = m ? v3_mul(tr, sigma_s) : tr, q = m ? v3_mul(tr, m->sigma_t) : tr;
    vec3 rq = v3_mul(ra, q);
    float mean_rq = mean3(rq);
    if (!(mean_rq > 0.0f) || !isfinite(mean_rq)) {
        ev.weight = v3s(0.0f);
        return ev;
    }
    ev.weight = v3_scale(f, mean3(ra) / mean_rq);
    mp->ratio = v3_scale(rq, 1.0f / mean_rq);
    return ev;
}
