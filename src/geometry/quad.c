// quad.c — building parallelogram quads and six-quad boxes; the intersection test is inline in quad.h.
#include "geometry/quad.h"

#include <math.h>

// Sets q->magnitude from its corners (whenever they are set).
static void set_magnitude(quad *q) {
    float m = 0.0f;
    for (int k = 0; k < 4; k++) {
        vec3 p = q->p[k];
        m = fmaxf(m, fmaxf(fabsf(p.x), fmaxf(fabsf(p.y), fabsf(p.z))));
    }
    q->magnitude = m;
}

bool quad_make(vec3 q, vec3 u, vec3 v, uint32_t material, quad *out) {
    if (!v3_is_finite(q) || !v3_is_finite(u) || !v3_is_finite(v)) return false;
    vec3 n = v3_cross(u, v);
    float area = v3_len(n);
    if (!(area > 0.0f) || !isfinite(area)) return false;
    out->q = q;
    out->u = u;
    out->v = v;
    out->p[0] = q;
    out->p[1] = v3_add(q, u);
    out->p[2] = v3_add(v3_add(q, u), v);
    out->p[3] = v3_add(q, v);
    out->normal = v3_scale(n, 1.0f / area);
    out->area = area;
    out->inv_len_u = 1.0f / v3_len(u); // finite: u x v is not zero, so neither is u nor v
    out->inv_len_v = 1.0f / v3_len(v);
    out->material = material;
    set_magnitude(out);
    return true;
}

// The one of lo, hi nearest to x: a box corner computed as q + u lands back exactly on the box.
static float snap(float x, float lo, float hi) { return fabsf(x - lo) <= fabsf(x - hi) ? lo : hi; }

bool quad_box(vec3 a, vec3 b, uint32_t material, quad out[6]) {
    vec3 lo = v3_min(a, b), hi = v3_max(a, b);
    vec3 dx = v3(hi.x - lo.x, 0, 0), dy = v3(0, hi.y - lo.y, 0), dz = v3(0, 0, hi.z - lo.z);
    // The book's order and orientation: front, right, back, left, top, bottom, each u x v outwards.
    bool ok = quad_make(v3(lo.x, lo.y, hi.z), dx, dy, material, &out[0]) &&
              quad_make(v3(hi.x, lo.y, hi.z), v3_neg(dz), dy, material, &out[1]) &&
              quad_make(v3(hi.x, lo.y, lo.z), v3_neg(dx), dy, material, &out[2]) &&
              quad_make(v3(lo.x, lo.y, lo.z), dz, dy, material, &out[3]) &&
              quad_make(v3(lo.x, hi.y, hi.z), dx, v3_neg(dz), material, &out[4]) &&
              quad_make(v3(lo.x, lo.y, lo.z), dx, dz, material, &out[5]);
    if (!ok) return false;
    for (int i = 0; i < 6; i++)
        for (int k = 0; k < 4; k++) {
            vec3 *p = &out[i].p[k];
            *p = v3(snap(p->x, lo.x, hi.x), snap(p->y, lo.y, hi.y), snap(p->z, lo.z, hi.z));
        }
    for (int i = 0; i < 6; i++) set_magnitude(&out[i]);
    return true;
}

bounds3 quad_bounds(const quad *q) {
    bounds3 b = bounds3_empty();
    for (int k = 0; k < 4; k++) b = bounds3_add(b, q->p[k]);
    return b;
}

bool quad_transform(const quad *q, const mat4 *m, quad *out) {
    vec3 p[4];
    for (int k = 0; k < 4; k++) p[k] = mat4_apply_point(m, q->p[k]);
    if (mat4_linear_det(m) < 0.0) {
        vec3 tmp = p[1];
        p[1] = p[3];
        p[3] = tmp;
    }
    if (!quad_make(p[0], v3_sub(p[1], p[0]), v3_sub(p[3], p[0]), q->material, out)) return false;
    for (int k = 0; k < 4; k++) out->p[k] = p[k];
    set_magnitude(out);
    return true;
}
