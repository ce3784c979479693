// vec.h — float 3-vectors and the small amount of linear algebra a ray tracer needs.
#ifndef GLINT_VEC_H
#define GLINT_VEC_H

#include <math.h>
#include <stdbool.h>

typedef struct vec3 {
    float x, y, z;
} vec3;

/// A ray: origin, direction (unit length in the path tracer), the open interval (tmin, tmax) with tmin >= 0 (the BVH's
/// box tests rely on it: bvh_kernel.h), and the time in the shutter at which it travels (what moving objects are
/// tested at; 0 unless the camera has a shutter).
typedef struct ray {
    vec3 o, d;
    float tmin, tmax;
    float time;
} ray;

static inline vec3 v3(float x, float y, float z) { return (vec3){x, y, z}; }
static inline vec3 v3s(float s) { return (vec3){s, s, s}; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline float v3_len2(vec3 a) { return v3_dot(a, a); }
static inline float v3_len(vec3 a) { return sqrtf(v3_dot(a, a)); }
static inline vec3 v3_unit(vec3 a) { return v3_scale(a, 1.0f / v3_len(a)); }
static inline vec3 v3_cross(vec3 a, vec3 b) {
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/// a + b * s, fused where the target has FMA.
static inline vec3 v3_fma(vec3 a, vec3 b, float s) {
    return v3(fmaf(b.x, s, a.x), fmaf(b.y, s, a.y), fmaf(b.z, s, a.z));
}
static inline vec3 v3_lerp(vec3 a, vec3 b, float t) { return v3_add(v3_scale(a, 1.0f - t), v3_scale(b, t)); }
/// fminf and fmaxf without the library call (they are calls at -O3 unless -ffinite-math-only, which this
/// code must not use): comparisons and a select, with fminf's NaN rule (a NaN operand yields the other).
static inline float f_min(float a, float b) { return (a < b || b != b) ? a : b; }
static inline float f_max(float a, float b) { return (a > b || b != b) ? a : b; }
static inline vec3 v3_min(vec3 a, vec3 b) { return v3(f_min(a.x, b.x), f_min(a.y, b.y), f_min(a.z, b.z)); }
static inline vec3 v3_max(vec3 a, vec3 b) { return v3(f_max(a.x, b.x), f_max(a.y, b.y), f_max(a.z, b.z)); }
static inline float v3_comp(vec3 a, int axis) { return axis == 0 ? a.x : (axis == 1 ? a.y : a.z); }
static inline float v3_max_comp(vec3 a) { return f_max(a.x, f_max(a.y, a.z)); }
/// max(|x|, |y|, |z|), with plain comparisons (fmaxf is a libm call at -O3 without -ffinite-math-only).
static inline float v3_max_abs(vec3 p) {
    float ax = fabsf(p.x), ay = fabsf(p.y), az = fabsf(p.z);
    return ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
}
static inline bool v3_is_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline bool v3_near_zero(vec3 a) {
    const float eps = 1e-8f;
    return fabsf(a.x) < eps && fabsf(a.y) < eps && fabsf(a.z) < eps;
}
static inline vec3 ray_at(const ray *r, float t) { return v3_fma(r->o, r->d, t); }

/// Mirror v about the plane with unit normal n: v - 2(v.n)n.
static inline vec3 v3_reflect(vec3 v, vec3 n) { return v3_sub(v, v3_scale(n, 2.0f * v3_dot(v, n))); }

/// Refract unit vector uv through unit normal n (facing against uv) with eta = n_incident / n_transmitted.
/// The caller checks for total internal reflection first (eta * sin(theta) > 1).
static inline vec3 v3_refract(vec3 uv, vec3 n, float eta) {
    float cos_theta = f_min(-v3_dot(uv, n), 1.0f);
    vec3 perp = v3_scale(v3_fma(uv, n, cos_theta), eta);
    vec3 para = v3_scale(n, -sqrtf(fabsf(1.0f - v3_len2(perp))));
    return v3_add(perp, para);
}

/// Schlick's approximation of Fresnel reflectance: r0 + (1 - r0)(1 - cos)^5, r0 = ((1 - n)/(1 + n))^2.
static inline float schlick_reflectance(float cosine, float ior_ratio) {
    float r0 = (1.0f - ior_ratio) / (1.0f + ior_ratio);
    r0 = r0 * r0;
    float m = 1.0f - cosine;
    return r0 + (1.0f - r0) * (m * m) * (m * m) * m;
}

/// An orthonormal basis around unit vector n (Duff et al. 2017, branchless).
static inline void v3_basis(vec3 n, vec3 *t, vec3 *b) {
    float sign = copysignf(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float bb = n.x * n.y * a;
    *t = v3(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
    *b = v3(bb, sign + n.y * n.y * a, -n.y);
}

#endif
