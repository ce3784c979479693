// microfacet.h — the GGX (Trowbridge–Reitz) microfacet distribution in a local frame (z the macro normal):
// its density D, the height-correlated Smith masking-shadowing G2, sampling of the distribution of visible
// normals (the spherical-cap form of Dupuy and Benyoub 2023, which draws what Heitz 2018 draws), and exact
// Fresnel reflectance of dielectrics and conductors. Plain math, shared by the BSDFs (bsdf.c) and the
// generator of their albedo tables (tools/make_bsdf_tables.c).
#ifndef GLINT_MICROFACET_H
#define GLINT_MICROFACET_H

#include "core/vec.h"

#include <math.h>
#include <stdbool.h>

/// The smallest GGX alpha: below it the lobe would be narrower than float can represent well (pbrt-v4 treats
/// alpha < 1e-3 as smooth); a roughness of 0 renders as this near-mirror.
#define MF_ALPHA_MIN 1e-3f

/// GGX alpha of a perceptual roughness r in [0, 1]: r^2 (glTF, Disney, Blender), at least MF_ALPHA_MIN.
static inline float mf_alpha(float roughness) {
    float a = roughness * roughness;
    return a > MF_ALPHA_MIN ? a : MF_ALPHA_MIN;
}

/// Smith's Lambda of direction w for the anisotropic GGX of alphas (ax, ay): G1 = 1 / (1 + Lambda).
static inline float mf_lambda(vec3 w, float ax, float ay) {
    float z2 = w.z * w.z;
    if (!(z2 > 0.0f)) return INFINITY;
    float t2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2; // alpha^2 tan^2(theta)
    return 0.5f * (sqrtf(1.0f + t2) - 1.0f);
}

/// Smith's masking of direction w (either hemisphere).
static inline float mf_g1(vec3 w, float ax, float ay) { return 1.0f / (1.0f + mf_lambda(w, ax, ay)); }

/// The height-correlated Smith masking-shadowing of the pair (wo, wi) (Heitz 2014, eq. 99).
static inline float mf_g2(vec3 wo, vec3 wi, float ax, float ay) {
    return 1.0f / (1.0f + mf_lambda(wo, ax, ay) + mf_lambda(wi, ax, ay));
}

/// The GGX density of micro-normal h (unit, h.z > 0), per unit solid angle times cos: integrates h.z D = 1.
static inline float mf_d(vec3 h, float ax, float ay) {
    if (!(h.z > 0.0f)) return 0.0f;
    float x = h.x / ax, y = h.y / ay, s = x * x + y * y + h.z * h.z;
    return 1.0f / (3.14159265358979f * ax * ay * s * s);
}

/// The density of the micro-normals visible from wo (wo.z > 0): G1(wo) max(0, wo.h) D(h) / wo.z.
static inline float mf_visible_d(vec3 wo, vec3 h, float ax, float ay) {
    float oh = v3_dot(wo, h);
    if (!(oh > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
    return mf_g1(wo, ax, ay) * oh * mf_d(h, ax, ay) / wo.z;
}

/// A micro-normal drawn from the visible normals of wo (wo.z > 0) with two uniform numbers u1, u2: the
/// direction is stretched to alpha 1, where the visible normals are a spherical cap's (Dupuy and Benyoub 2023),
/// and the normal unstretched.
static inline vec3 mf_sample_visible(vec3 wo, float ax, float ay, float u1, float u2) {
    vec3 v = v3_unit(v3(ax * wo.x, ay * wo.y, wo.z));
    float phi = 6.28318530717959f * u1;
    float z = (1.0f - u2) * (1.0f + v.z) - v.z; // uniform in (-v.z, 1]
    float s = 1.0f - z * z;
    s = sqrtf(s > 0.0f ? s : 0.0f);
    vec3 h = v3(s * cosf(phi) + v.x, s * sinf(phi) + v.y, z + v.z);
    h = v3(ax * h.x, ay * h.y, h.z > 1e-7f ? h.z : 1e-7f);
    return v3_unit(h);
}

/// Fresnel reflectance of a dielectric interface for light arriving at cos_i >= 0 to the normal on the side
/// where the other medium's index over this one's is etap (> 1: entering the denser medium); 1 under total
/// internal reflection. Unpolarised: the mean of the s and p reflectances.
static inline float mf_fresnel_dielectric(float cos_i, float etap) {
    cos_i = cos_i < 1.0f ? cos_i : 1.0f;
    float sin2_t = (1.0f - cos_i * cos_i) / (etap * etap);
    if (sin2_t >= 1.0f) return 1.0f;
    float cos_t = sqrtf(1.0f - sin2_t);
    float r_par = (etap * cos_i - cos_t) / (etap * cos_i + cos_t);
    float r_perp = (cos_i - etap * cos_t) / (cos_i + etap * cos_t);
    return 0.5f * (r_par * r_par + r_perp * r_perp);
}

/// Fresnel reflectance of a conductor of complex index eta + i k (one channel) at cos_i in [0, 1], exact for
/// unpolarised light (the a^2 + b^2 form of Born and Wolf as written by Lagarde, "Memo on Fresnel equations").
static inline float mf_fresnel_conductor1(float cos_i, float eta, float k) {
    cos_i = cos_i < 0.0f ? 0.0f : cos_i > 1.0f ? 1.0f : cos_i;
    float c2 = cos_i * cos_i, s2 = 1.0f - c2;
    float t0 = eta * eta - k * k - s2;
    float a2b2 = sqrtf(t0 * t0 + 4.0f * eta * eta * k * k);
    float a = sqrtf(fmaxf(0.5f * (a2b2 + t0), 0.0f));
    float t1 = a2b2 + c2, t2 = 2.0f * a * cos_i;
    float rs = (t1 - t2) / (t1 + t2);
    float t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
    float rp = rs * (t3 - t4) / (t3 + t4);
    float f = 0.5f * (rp + rs);
    return f == f ? f : 1.0f; // 0/0 at grazing incidence: a conductor reflects everything there
}

/// Schlick's reflectance f0 + (1 - f0)(1 - cos)^5 per channel.
static inline vec3 mf_fresnel_schlick(vec3 f0, float cos_i) {
    float m = 1.0f - (cos_i < 1.0f ? cos_i : 1.0f), m2 = m * m, m5 = m2 * m2 * m;
    return v3_add(f0, v3_scale(v3_sub(v3s(1.0f), f0), m5));
}

/// The mirror image of w about unit h.
static inline vec3 mf_reflect(vec3 w, vec3 h) { return v3_sub(v3_scale(h, 2.0f * v3_dot(w, h)), w); }

/// The refraction of w (pointing away from the surface, w.h > 0) through micro-normal h into the medium whose
/// index over w's is etap; false under total internal reflection.
static inline bool mf_refract(vec3 w, vec3 h, float etap, vec3 *out) {
    float cos_i = v3_dot(w, h);
    float sin2_t = (1.0f - cos_i * cos_i) / (etap * etap);
    if (sin2_t >= 1.0f) return false;
    float cos_t = sqrtf(1.0f - sin2_t);
    *out = v3_sub(v3_scale(v3_neg(w), 1.0f / etap), v3_scale(h, cos_t - cos_i / etap));
    return true;
}

#endif
