// mesh.c — bounds, shading data, smooth vertex normals and baked transforms of triangle meshes.
#include "geometry/mesh.h"
#include "core/prefetch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void mesh_free(mesh *m) {
    free(m->positions);
    free(m->normals);
    free(m->uvs);
    free(m->triangles);
    free(m->normal_corners);
    free(m->uv_corners);
    memset(m, 0, sizeof *m);
    m->bounds = bounds3_empty();
}

void mesh_drop_normals(mesh *m) {
    free(m->normals);
    free(m->normal_corners);
    m->normals = NULL;
    m->normal_count = 0;
    m->normal_corners = NULL;
    m->smooth = false;
    m->smooth_base = 0;
}

bounds3 mesh_compute_bounds(mesh *m) {
    bounds3 b = bounds3_empty();
    for (size_t i = 0; i < m->triangle_count; i++) b = bounds3_union(b, mesh_triangle_bounds(m, i));
    m->bounds = b;
    return b;
}

// n / |n|, or `fallback` when n is zero or not finite.
static vec3 unit_or(vec3 n, vec3 fallback) {
    float len = v3_len(n);
    if (!(len > 0.0f) || !isfinite(len)) return fallback;
    vec3 u = v3_scale(n, 1.0f / len);
    return v3_is_finite(u) ? u : fallback;
}

mesh_shading mesh_shade(const mesh *m, size_t tri, const tri_hit *h) {
    mesh_corners n = mesh_triangle_normals(m, tri), t = mesh_triangle_uvs(m, tri);
    mesh_shading s;
    vec3 p0, p1, p2;
    mesh_triangle_positions(m, tri, &p0, &p1, &p2);
    float k;
    s.magnitude = v3_max_abs(p0);
    s.magnitude = (k = v3_max_abs(p1)) > s.magnitude ? k : s.magnitude;
    s.magnitude = (k = v3_max_abs(p2)) > s.magnitude ? k : s.magnitude;
    s.ng = unit_or(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)), v3(0, 0, 1));
    s.ns = s.ng;
    if (mesh_corners_complete(n)) {
        vec3 sum = v3_scale(m->normals[n.i[0]], h->b0);
        sum = v3_fma(sum, m->normals[n.i[1]], h->b1);
        sum = v3_fma(sum, m->normals[n.i[2]], h->b2);
        s.ns = unit_or(sum, s.ng);
        // As pbrt: the file's normals say which side is outside, whatever the winding.
        if (v3_dot(s.ng, s.ns) < 0.0f) s.ng = v3_neg(s.ng);
    }
    if (mesh_corners_complete(t)) {
        uv2 a = m->uvs[t.i[0]], b = m->uvs[t.i[1]], c = m->uvs[t.i[2]];
        s.u = h->b0 * a.u + h->b1 * b.u + h->b2 * c.u;
        s.v = h->b0 * a.v + h->b1 * b.v + h->b2 * c.v;
    } else {
        s.u = h->b1;
        s.v = h->b2;
    }
    return s;
}

// Triangles ahead whose corners are fetched into the cache: a large mesh's triangles reach vertices all over
// its arrays, and waiting for each one in turn would cost more than the arithmetic.
enum { NORMALS_PREFETCH_AHEAD = 8 };

bool mesh_compute_normals(mesh *m) {
    size_t np = m->position_count, nt = m->triangle_count;
    if (np == 0) return true;
    if (np > (size_t)INT32_MAX - m->normal_count) return false;
    vec3 *normals = realloc(m->normals, (m->normal_count + np) * sizeof *normals);
    if (!normals) return false;
    m->normals = normals;
    vec3 *acc = normals + m->normal_count;
    for (size_t i = 0; i < np; i++) acc[i] = v3s(0.0f);
    const vec3 *pos = m->positions;
    const mesh_triangle *tris = m->triangles;
    mesh_corners *corners = m->normal_corners;
    int32_t base = (int32_t)m->normal_count;
    for (size_t i = 0; i < nt; i++) {
        if (i + NORMALS_PREFETCH_AHEAD < nt) {
            const int32_t *ahead = tris[i + NORMALS_PREFETCH_AHEAD].v;
            for (int k = 0; k < 3; k++) {
                prefetch_read(&pos[ahead[k]]);
                prefetch_write(&acc[ahead[k]]);
            }
        }
        const mesh_triangle *t = &tris[i];
        // The unnormalised cross product is twice the area times the unit normal: area weighting for free.
        vec3 p0 = pos[t->v[0]], p1 = pos[t->v[1]], p2 = pos[t->v[2]];
        vec3 n = v3_cross(v3_sub(p1, p0), v3_sub(p2, p0));
        if (v3_is_finite(n))
            for (int k = 0; k < 3; k++) acc[t->v[k]] = v3_add(acc[t->v[k]], n);
        // Triangles without complete normals of their own get their vertices' (normalised below).
        if (corners && !mesh_corners_complete(corners[i]))
            for (int k = 0; k < 3; k++) corners[i].i[k] = base + t->v[k];
    }
    for (size_t i = 0; i < np; i++) acc[i] = unit_or(acc[i], v3s(0.0f));
    // Without normals of their own, every triangle's are its vertices': indexed like positions, stored once.
    if (!corners && !m->smooth) {
        m->smooth = true;
        m->smooth_base = base;
    }
    m->normal_count += np;
    return true;
}

void mesh_apply_transform(mesh *m, const transform *t) {
    for (size_t i = 0; i < m->position_count; i++) m->positions[i] = mat4_apply_point(&t->m, m->positions[i]);
    for (size_t i = 0; i < m->normal_count; i++)
        m->normals[i] = unit_or(mat4_apply_normal(&t->inv, m->normals[i]), m->normals[i]);
    const float (*a)[4] = t->m.m;
    double det = (double)a[0][0] * ((double)a[1][1] * a[2][2] - (double)a[1][2] * a[2][1]) -
                 (double)a[0][1] * ((double)a[1][0] * a[2][2] - (double)a[1][2] * a[2][0]) +
                 (double)a[0][2] * ((double)a[1][0] * a[2][1] - (double)a[1][1] * a[2][0]);
    if (det < 0.0) {
        // A mirror turns counter-clockwise into clockwise: swap two corners to keep the geometric normal outwards.
        for (size_t i = 0; i < m->triangle_count; i++) {
            int32_t *c[3] = {m->triangles[i].v, m->normal_corners ? m->normal_corners[i].i : NULL,
                             m->uv_corners ? m->uv_corners[i].i : NULL};
            for (int k = 0; k < 3; k++) {
                if (!c[k]) continue;
                int32_t tmp = c[k][1];
                c[k][1] = c[k][2];
                c[k][2] = tmp;
            }
        }
    }
    mesh_compute_bounds(m);
}
