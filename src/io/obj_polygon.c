// obj_polygon.c — faces into triangles: a triangle as it is, a convex polygon (on the plane of its Newell normal)
// as a fan, a concave one by ear clipping; each triangle appended to the mesh with its corners' normals and
// texture coordinates, and the mesh's box grown by it.
#include "core/array.h"
#include "io/obj_parser.h"

#include <math.h>
#include <stdlib.h>

// Whether the triangle (p, q, r) has exactly zero area: its edge cross product, in double, is zero.
static bool zero_area(vec3 p, vec3 q, vec3 r) {
    double ux = (double)q.x - p.x, uy = (double)q.y - p.y, uz = (double)q.z - p.z;
    double vx = (double)r.x - p.x, vy = (double)r.y - p.y, vz = (double)r.z - p.z;
    return uy * vz - uz * vy == 0.0 && uz * vx - ux * vz == 0.0 && ux * vy - uy * vx == 0.0;
}

// f_min and f_max (core/vec.h) for operands that are not NaN, as every coordinate read is: without their NaN
// rule the comparison compiles to one minss or maxss instead of a branch that random data mispredicts.
static inline float min_not_nan(float a, float b) { return a < b ? a : b; }
static inline float max_not_nan(float a, float b) { return a > b ? a : b; }

// bounds3_union(box, tri_bounds(p, q, r)), operand for operand, for points without NaN.
static inline bounds3 box_add_triangle(bounds3 box, vec3 p, vec3 q, vec3 r) {
    vec3 lo = v3(min_not_nan(p.x, min_not_nan(q.x, r.x)), min_not_nan(p.y, min_not_nan(q.y, r.y)),
                 min_not_nan(p.z, min_not_nan(q.z, r.z)));
    vec3 hi = v3(max_not_nan(p.x, max_not_nan(q.x, r.x)), max_not_nan(p.y, max_not_nan(q.y, r.y)),
                 max_not_nan(p.z, max_not_nan(q.z, r.z)));
    return (bounds3){v3(min_not_nan(box.lo.x, lo.x), min_not_nan(box.lo.y, lo.y), min_not_nan(box.lo.z, lo.z)),
                     v3(max_not_nan(box.hi.x, hi.x), max_not_nan(box.hi.y, hi.y), max_not_nan(box.hi.z, hi.z))};
}

// Stores triangle i's corner indices (x, y, z) into normals or uvs in *list. The list starts with the first
// triangle that has one, all -1 before it, so that a mesh without any stores none. False when out of memory.
static bool store_corners(mesh_corners **list, size_t *cap, size_t i, int32_t x, int32_t y, int32_t z) {
    if (!*list && x < 0 && y < 0 && z < 0) return true;
    bool first = !*list;
    if (i >= *cap && !array_reserve((void **)list, cap, i + 1, sizeof **list)) return false;
    for (size_t k = 0; first && k < i; k++) (*list)[k] = (mesh_corners){{-1, -1, -1}};
    (*list)[i] = (mesh_corners){{x, y, z}};
    return true;
}

// Appends triangle (a, b, c) at positions (p, q, r), and grows the mesh's box by it while its corners are at
// hand (the box mesh_compute_bounds would compute, union for union in the same order).
static bool append_triangle(obj_parser *ps, const obj_corner *a, const obj_corner *b, const obj_corner *c, vec3 p, vec3 q, vec3 r) {
    mesh *m = &ps->model->mesh;
    size_t i = m->triangle_count;
    if (i >= OBJ_MAX_ELEMENTS) return obj_too_many(&ps->rep, "triangles");
    if ((i == ps->tri_cap && !array_reserve((void **)&m->triangles, &ps->tri_cap, i + 1, sizeof *m->triangles)) ||
        !store_corners(&m->normal_corners, &ps->nrm_corner_cap, i, a->n, b->n, c->n) ||
        !store_corners(&m->uv_corners, &ps->uv_corner_cap, i, a->t, b->t, c->t))
        return obj_out_of_memory(&ps->rep);
    m->triangles[i] = (mesh_triangle){{a->v, b->v, c->v}, ps->material};
    m->triangle_count = i + 1;
    m->bounds = box_add_triangle(m->bounds, p, q, r);
    return true;
}

// Appends triangle (a, b, c) unless it has no area (degenerate pieces of a valid polygon are dropped silently).
static bool emit(obj_parser *ps, const obj_corner *a, const obj_corner *b, const obj_corner *c) {
    const vec3 *pos = ps->model->mesh.positions;
    vec3 p = pos[a->v], q = pos[b->v], r = pos[c->v];
    return zero_area(p, q, r) || append_triangle(ps, a, b, c, p, q, r);
}

static void zero_area_face(obj_parser *ps) {
    if (ps->model->zero_area_faces++ == 0) {
        ps->first_zero_line = ps->rep.line;
        obj_warn_at(&ps->rep, ps->rep.line, "face has zero area; skipped");
    }
}

static double cross2(const obj_parser *ps, int a, int b, int c) {
    return (ps->px[b] - ps->px[a]) * (ps->py[c] - ps->py[a]) - (ps->py[b] - ps->py[a]) * (ps->px[c] - ps->px[a]);
}

// Ear clipping of the projected polygon of n corners with orientation sign s (> 0: counter-clockwise).
static bool ear_clip(obj_parser *ps, size_t n, double s) {
    const obj_corner *k = ps->corners;
    for (size_t i = 0; i < n; i++) {
        ps->next[i] = (int)((i + 1) % n);
        ps->prev[i] = (int)((i + n - 1) % n);
    }
    size_t remaining = n;
    int i = 0;
    while (remaining > 3) {
        bool clipped = false;
        for (size_t tries = 0; tries < remaining && !clipped; tries++, i = ps->next[i]) {
            int p = ps->prev[i], q = ps->next[i];
            if (cross2(ps, p, i, q) * s <= 0.0) continue; // reflex or straight: not an ear
            bool empty = true;
            for (int r = ps->next[q]; r != p && empty; r = ps->next[r]) {
                // Corners that coincide with the ear's (the bridge of a keyhole polygon) do not block it.
                bool same = (ps->px[r] == ps->px[p] && ps->py[r] == ps->py[p]) ||
                            (ps->px[r] == ps->px[i] && ps->py[r] == ps->py[i]) ||
                            (ps->px[r] == ps->px[q] && ps->py[r] == ps->py[q]);
                if (!same && cross2(ps, p, i, r) * s >= 0.0 && cross2(ps, i, q, r) * s >= 0.0 &&
                    cross2(ps, q, p, r) * s >= 0.0)
                    empty = false;
            }
            if (!empty) continue;
            if (!emit(ps, &k[p], &k[i], &k[q])) return false;
            ps->next[p] = q;
            ps->prev[q] = p;
            remaining--;
            clipped = true;
            i = p; // the loop's step moves on to q, whose ear status changed
        }
        if (clipped) continue;
        // No ear: drop a straight corner (no area lost) if there is one, else clip anyway and say so.
        int victim = -1;
        for (size_t t = 0, j = (size_t)i; t < remaining && victim < 0; t++, j = (size_t)ps->next[j])
            if (cross2(ps, ps->prev[j], (int)j, ps->next[j]) == 0.0) victim = (int)j;
        if (victim < 0) {
            victim = i;
            if (!ps->warned_bad_polygon) {
                ps->warned_bad_polygon = true;
                obj_warn_at(&ps->rep, ps->rep.line, "face is self-intersecting; its triangulation may be wrong");
            }
            if (!emit(ps, &k[ps->prev[victim]], &k[victim], &k[ps->next[victim]])) return false;
        }
        ps->next[ps->prev[victim]] = ps->next[victim];
        ps->prev[ps->next[victim]] = ps->prev[victim];
        i = ps->next[victim];
        remaining--;
    }
    return emit(ps, &k[ps->prev[i]], &k[i], &k[ps->next[i]]);
}

// Whether every corner of the projected face turns the way of the face (sign s), or the other way by no
// more than moving its three points by the rounding of their coordinates to float could cause. The error of
// (b - a) x (c - a) when each coordinate is off by up to e is at most 2e (|b - a|_1 + |c - a|_1) + 8e^2; it
// is doubled to be safe.
static bool convex_within_rounding(const obj_parser *ps, size_t n, double s) {
    for (size_t i = 0; i < n; i++) {
        int a = (int)((i + n - 1) % n), b = (int)i, c = (int)((i + 1) % n);
        double turn = cross2(ps, a, b, c) * s;
        if (turn >= 0.0) continue;
        double m = fmax(fmax(fmax(fabs(ps->px[a]), fabs(ps->py[a])), fmax(fabs(ps->px[b]), fabs(ps->py[b]))),
                        fmax(fabs(ps->px[c]), fabs(ps->py[c])));
        double e = 0x1p-24 * m;
        double l1 = fabs(ps->px[b] - ps->px[a]) + fabs(ps->py[b] - ps->py[a]) + fabs(ps->px[c] - ps->px[a]) +
                    fabs(ps->py[c] - ps->py[a]);
        if (-turn > 2.0 * (2.0 * e * l1 + 8.0 * e * e)) return false;
    }
    return true;
}

static bool fan(obj_parser *ps, size_t n) {
    for (size_t i = 1; i + 1 < n; i++)
        if (!emit(ps, &ps->corners[0], &ps->corners[i], &ps->corners[i + 1])) return false;
    return true;
}

// A face of three corners: skipped, with a warning, when it has no area.
bool obj_triangle_face(obj_parser *ps, const obj_corner *k) {
    const vec3 *pos = ps->model->mesh.positions;
    vec3 p = pos[k[0].v], q = pos[k[1].v], r = pos[k[2].v];
    if (zero_area(p, q, r)) {
        zero_area_face(ps);
        return true;
    }
    return append_triangle(ps, &k[0], &k[1], &k[2], p, q, r);
}

// Splits the face's n corners into triangles: fan when convex, ear clipping when concave.
bool obj_triangulate(obj_parser *ps, size_t n) {
    const mesh *m = &ps->model->mesh;
    const obj_corner *k = ps->corners;
    if (n == 3) return obj_triangle_face(ps, k);
    // Newell's normal: robust for non-planar faces, zero when the face has no area.
    double nx = 0, ny = 0, nz = 0;
    for (size_t i = 0; i < n; i++) {
        vec3 a = m->positions[k[i].v], b = m->positions[k[(i + 1) % n].v];
        nx += ((double)a.y - b.y) * ((double)a.z + b.z);
        ny += ((double)a.z - b.z) * ((double)a.x + b.x);
        nz += ((double)a.x - b.x) * ((double)a.y + b.y);
    }
    double ax = fabs(nx), ay = fabs(ny), az = fabs(nz);
    if (!(ax > 0 || ay > 0 || az > 0) || !isfinite(ax + ay + az)) {
        zero_area_face(ps);
        return true;
    }
    if (n > ps->scratch_cap) {
        // All four scratch arrays share one capacity; each reserve grows its own copy of it.
        size_t c1 = ps->scratch_cap, c2 = c1, c3 = c1, c4 = c1;
        if (!array_reserve((void **)&ps->px, &c1, n, sizeof *ps->px) || !array_reserve((void **)&ps->py, &c2, n, sizeof *ps->py) ||
            !array_reserve((void **)&ps->next, &c3, n, sizeof *ps->next) || !array_reserve((void **)&ps->prev, &c4, n, sizeof *ps->prev))
            return obj_out_of_memory(&ps->rep);
        ps->scratch_cap = c1;
    }
    // Project on the plane of the largest normal component; the cyclic axis order makes the sign of the
    // projected area the sign of that component.
    int axis = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    double s = (axis == 0 ? nx : axis == 1 ? ny : nz) > 0 ? 1.0 : -1.0;
    for (size_t i = 0; i < n; i++) {
        vec3 p = m->positions[k[i].v];
        ps->px[i] = axis == 0 ? p.y : axis == 1 ? p.z : p.x;
        ps->py[i] = axis == 0 ? p.z : axis == 1 ? p.x : p.y;
    }
    bool convex = true;
    for (size_t i = 0; i < n && convex; i++)
        convex = cross2(ps, (int)((i + n - 1) % n), (int)i, (int)((i + 1) % n)) * s >= 0.0;
    if (convex) return fan(ps, n);
    if (n > OBJ_MAX_EAR_CLIP) {
        // Too many corners for ear clipping: a fan, which is right when the face is convex but for the
        // rounding of its corners (a finely divided circle), and worth a warning only when it is not.
        if (!convex_within_rounding(ps, n, s) && !ps->warned_fan) {
            ps->warned_fan = true;
            obj_warn_at(&ps->rep, ps->rep.line, "concave face with %zu vertices triangulated as a fan; it may be wrong", n);
        }
        return fan(ps, n);
    }
    return ear_clip(ps, n, s);
}
