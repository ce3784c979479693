// scatter.h — how a material turns an incoming ray into an outgoing one in the path tracer: the book's
// Lambertian, metal and dielectric, and the paper's Phong material as a diffuse/mirror mixture.
#ifndef GLINT_SCATTER_H
#define GLINT_SCATTER_H

#include "core/rng.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "material/material.h"
#include "material/texture.h"

#include <stdbool.h>

/// One scattering event: where the path goes next and how much of its throughput survives.
typedef struct scatter_event {
    vec3 dir;     ///< unit direction of the new ray
    vec3 weight;  ///< throughput factor f cos / pdf of the sampled direction
    bool diffuse; ///< the ideal diffuse lobe (BRDF weight / pi) was chosen, so next-event estimation applies
    bool transmitted; ///< the ray crossed the surface (dielectric refraction) rather than reflecting
} scatter_event;

/// The material's albedo (Lambertian/metal albedo, Phong colour, dielectric tint) at surface coordinates
/// (u, v) and point p: the value of its albedo texture in `textures` there, or the constant `albedo`.
static inline vec3 mat_albedo(const material *m, const texture *textures, float u, float v, vec3 p) {
    if (m->albedo_texture < 0) return m->albedo;
    return texture_value(&textures[m->albedo_texture], u, v, p);
}

/// The book's Lambertian direction from unit normal n and a uniform unit vector u, not normalised: n + u,
/// whose direction has density cos/pi; n itself when n + u is (nearly) zero or, by rounding, not above the
/// surface. Its length lies in (1e-6, 2].
static inline vec3 mat_lambertian_sum(vec3 n, vec3 u) {
    vec3 s = v3_add(n, u);
    // |n + u| < 1e-6 has probability ~2.5e-13; there the sum's direction is rounding noise.
    if (v3_len2(s) < 1e-12f || !(v3_dot(s, n) > 0.0f)) return n;
    return s;
}

/// The book's Lambertian direction: unit(n + u) (mat_lambertian_sum), whose density is cos/pi.
static inline vec3 mat_lambertian_dir(vec3 n, vec3 u) {
    vec3 s = v3_add(n, u);
    if (v3_len2(s) < 1e-12f || !(v3_dot(s, n) > 0.0f)) return n;
    return v3_unit(s);
}

/// The book's fuzzy mirror: unit(reflect(d, n)) + fuzz u, normalised, for unit d and n and a uniform unit
/// vector u; false (the path is absorbed) when it does not point above the surface.
static inline bool mat_metal_dir(vec3 d, vec3 n, float fuzz, vec3 u, vec3 *out) {
    vec3 s = v3_fma(v3_reflect(d, n), u, fuzz); // the mirror image of a unit d is unit already
    if (!(v3_dot(s, n) > 0.0f) || v3_len2(s) < 1e-12f) return false;
    *out = v3_unit(s);
    return true;
}

/// The density (per steradian) with which mat_metal_dir draws unit direction wi around the unit mirror direction
/// `mirror`, for 0 < fuzz <= 1, absorbed samples included (they are the directions below the surface): the point
/// mirror + fuzz u, u uniform on the unit sphere, lies on a sphere of radius fuzz, and wi's ray from the origin
/// meets it at distances c -+ D (c = wi.mirror, D^2 = fuzz^2 - |wi x mirror|^2), each point's area density
/// 1 / (4 pi fuzz^2) seen under the solid angle s^2 / |u.wi| = s^2 fuzz / D: together (c^2 + D^2) / (2 pi fuzz D),
/// cos/pi about the mirror direction at fuzz 1. Infinite (integrably) at the edge of the cone, zero outside it.
static inline float mat_metal_pdf(vec3 mirror, float fuzz, vec3 wi) {
    float c = v3_dot(wi, mirror);
    vec3 x = v3_cross(wi, mirror);
    float d2 = fuzz * fuzz - v3_dot(x, x); // sin^2 from the cross product: no cancellation in narrow cones
    if (!(c > 0.0f) || !(d2 > 0.0f)) return 0.0f;
    float d = sqrtf(d2);
    return (c * c + d2) / (6.283185307179586f * fuzz * d);
}

/// Probability that a dielectric reflects a ray arriving at cos_i to the normal, with eta = n_incident /
/// n_transmitted: 1 under total internal reflection, else Schlick's r0 + (1 - r0)(1 - cos_i)^5 (as the book).
static inline float mat_dielectric_reflectance(float cos_i, float eta) {
    float sin2 = 1.0f - cos_i * cos_i;
    float sin_i = sqrtf(sin2 > 0.0f ? sin2 : 0.0f);
    if (eta * sin_i > 1.0f) return 1.0f;
    return schlick_reflectance(cos_i, eta);
}

/// The book's dielectric for unit d and unit n facing against d: the mirror direction with probability
/// mat_dielectric_reflectance (xi uniform in [0, 1)), else the Snell refraction; *reflected says which.
static inline vec3 mat_dielectric_dir(vec3 d, vec3 n, float eta, float xi, bool *reflected) {
    float cos_i = -v3_dot(d, n);
    cos_i = cos_i < 1.0f ? cos_i : 1.0f;
    *reflected = xi < mat_dielectric_reflectance(cos_i, eta);
    if (*reflected) return v3_reflect(d, n);
    return v3_unit(v3_refract(d, n, eta));
}

/// Radiance a material (diffuse_light, or pbr's emission) emits towards a ray that met it on its front
/// (outward-normal) side or its back, at surface coordinates (u, v) and point p: `emission`, times its
/// emission texture's value when it has one.
static inline vec3 mat_emitted(const material *m, const texture *textures, bool front, float u, float v, vec3 p) {
    if ((m->kind != MAT_DIFFUSE_LIGHT && m->kind != MAT_PBR) || !(front || m->two_sided)) return v3s(0.0f);
    if (m->emission_texture < 0) return m->emission;
    return v3_mul(m->emission, texture_value(&textures[m->emission_texture], u, v, p));
}

/// Samples how m, of albedo `albedo` at this point (mat_albedo), scatters a ray of unit direction d at a
/// surface with unit normal n facing against d (front: d arrived on the outward side); false when the path
/// ends there (absorbed, or an emitter). One random decision per event, the throughput weight computed so
/// that its expectation is the BSDF's reflectance. Always inlined: the path tracer's loop calls it in two
/// places, and out of line (as gcc otherwise leaves it) the call cost the lean bounce its gain.
static inline __attribute__((always_inline)) bool mat_scatter(const material *m, vec3 albedo, vec3 d, vec3 n,
                                                            bool front, rng *r, scatter_event *ev) {
    ev->diffuse = false;
    ev->transmitted = false;
    switch (m->kind) {
    case MAT_LAMBERTIAN:
        ev->dir = mat_lambertian_dir(n, sample_sphere_uniform(r));
        ev->weight = albedo; // (albedo / pi) cos / (cos / pi)
        ev->diffuse = true;
        return true;
    case MAT_METAL:
        ev->weight = albedo;
        return mat_metal_dir(d, n, m->fuzz, sample_sphere_uniform(r), &ev->dir);
    case MAT_DIELECTRIC: {
        bool reflected;
        float eta = front ? 1.0f / m->ior : m->ior;
        ev->dir = mat_dielectric_dir(d, n, eta, rng_float(r), &reflected);
        ev->transmitted = !reflected;
        ev->weight = albedo; // the tint; (1,1,1) is clear glass
        return true;
    }
    case MAT_PHONG:
        // The paper's colour blend (1 - rfl) diffuse + rfl mirror, as a random choice of one of the two.
        if (rng_float(r) < m->reflective) {
            ev->dir = v3_reflect(d, n);
            ev->weight = v3s(1.0f);
            return true;
        }
        ev->dir = mat_lambertian_dir(n, sample_sphere_uniform(r));
        ev->weight = albedo;
        ev->diffuse = true;
        return true;
    case MAT_DIFFUSE_LIGHT: return false;
    case MAT_CONDUCTOR: // placeholder: diffuse until the BSDF interface takes the microfacet materials
    case MAT_ROUGH_DIELECTRIC:
    case MAT_PBR:
    case MAT_KIND_COUNT:
        ev->dir = mat_lambertian_dir(n, sample_sphere_uniform(r));
        ev->weight = albedo;
        ev->diffuse = true;
        return true;
    }
    return false;
}

#endif
