// mesh.h — an indexed triangle mesh: shared positions, normals and texture coordinates, triangles that index
// them per corner (normals and texture coordinates in arrays of their own, only when some triangle has them),
// a per-triangle material slot, and the shading data of a hit.
#ifndef GLINT_MESH_H
#define GLINT_MESH_H

#include "core/prefetch.h"
#include "core/vec.h"
#include "geometry/transform.h"
#include "geometry/triangle.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// A texture coordinate.
typedef struct uv2 {
    float u, v;
} uv2;

/// One triangle: per corner an index into positions; its material. 16 bytes: a large mesh's biggest array.
typedef struct mesh_triangle {
    int32_t v[3];
    int32_t material; ///< slot in the mesh's own material list (see obj_model); -1: the mesh's scene material
} mesh_triangle;

/// Per corner of a triangle, an index into a mesh's normals or uvs (-1: none).
typedef struct mesh_corners {
    int32_t i[3];
} mesh_corners;

/// A triangle mesh. Counts fit in int32_t; all arrays are owned (malloc) and freed by mesh_free(). Read a
/// triangle's normal and uv indices through mesh_triangle_normals and mesh_triangle_uvs: most large meshes
/// have no uvs and only computed smooth normals, indexed like their positions, and then store no indices.
typedef struct mesh {
    vec3 *positions;
    size_t position_count;
    vec3 *normals;
    size_t normal_count;
    uv2 *uvs;
    size_t uv_count;
    mesh_triangle *triangles;
    size_t triangle_count;
    mesh_corners *normal_corners; ///< per triangle, its normals; NULL: as `smooth` says
    mesh_corners *uv_corners;     ///< per triangle, its uvs; NULL: no triangle has uvs
    bool smooth;                  ///< without normal_corners: corner k of a triangle has normal smooth_base + v[k]
                                  ///< (false: no triangle has normals)
    int32_t smooth_base;
    bounds3 bounds; ///< of the vertices of the triangles (mesh_compute_bounds)
} mesh;

/// Shading data of a triangle hit.
typedef struct mesh_shading {
    vec3 ng;    ///< unit geometric normal; (p1 - p0) x (p2 - p0), turned to the side of ns when normals are given
    vec3 ns;    ///< unit shading normal: interpolated vertex normals (smooth shading), else ng
    float u, v; ///< interpolated texture coordinates, else the barycentrics (b1, b2)
    float magnitude; ///< the largest |coordinate| of the corners: what the error of intersecting it scales with
} mesh_shading;

/// Frees the arrays and leaves an empty mesh.
void mesh_free(mesh *m);
/// Drops every normal: each triangle is shaded with its geometric normal (flat shading).
void mesh_drop_normals(mesh *m);
/// Sets and returns m->bounds: the box of every vertex used by a triangle (empty for no triangles).
bounds3 mesh_compute_bounds(mesh *m);
/// Shading data at barycentrics h of triangle `tri` (normals interpolated when all three corners have one).
mesh_shading mesh_shade(const mesh *m, size_t tri, const tri_hit *h);
/// Gives every triangle without complete vertex normals smooth ones: per position, the area-weighted mean of
/// the normals of the triangles around it (appended to m->normals). False when out of memory (m unchanged).
bool mesh_compute_normals(mesh *m);
/// Applies t to positions and normals in place (mirrors swap the winding so fronts stay fronts), then
/// recomputes the bounds.
void mesh_apply_transform(mesh *m, const transform *t);

/// The normal indices of triangle i's corners (-1: none).
static inline mesh_corners mesh_triangle_normals(const mesh *m, size_t i) {
    if (m->normal_corners) return m->normal_corners[i];
    if (!m->smooth) return (mesh_corners){{-1, -1, -1}};
    const int32_t *v = m->triangles[i].v, b = m->smooth_base;
    return (mesh_corners){{b + v[0], b + v[1], b + v[2]}};
}

/// The uv indices of triangle i's corners (-1: none).
static inline mesh_corners mesh_triangle_uvs(const mesh *m, size_t i) {
    return m->uv_corners ? m->uv_corners[i] : (mesh_corners){{-1, -1, -1}};
}

/// Whether every corner has an index (a normal or a uv to interpolate).
static inline bool mesh_corners_complete(mesh_corners c) { return c.i[0] >= 0 && c.i[1] >= 0 && c.i[2] >= 0; }

/// The three corner positions of triangle i.
static inline void mesh_triangle_positions(const mesh *m, size_t i, vec3 *p0, vec3 *p1, vec3 *p2) {
    const mesh_triangle *tri = &m->triangles[i];
    *p0 = m->positions[tri->v[0]];
    *p1 = m->positions[tri->v[1]];
    *p2 = m->positions[tri->v[2]];
}

/// Starts fetching what mesh_shade reads of triangle i beyond its record (which this reads): the corners' positions
/// and normals, scattered over arrays too large for the cache on a big mesh (uvs, rare on big meshes, come on
/// demand). Always inlined, as core/prefetch.h says.
static inline __attribute__((always_inline)) void mesh_prefetch_shade(const mesh *m, size_t i) {
    const int32_t *v = m->triangles[i].v;
    prefetch_read(&m->positions[v[0]]);
    prefetch_read(&m->positions[v[1]]);
    prefetch_read(&m->positions[v[2]]);
    mesh_corners n = mesh_triangle_normals(m, i);
    if (!mesh_corners_complete(n)) return;
    prefetch_read(&m->normals[n.i[0]]);
    prefetch_read(&m->normals[n.i[1]]);
    prefetch_read(&m->normals[n.i[2]]);
}

/// Bounds of triangle i.
static inline bounds3 mesh_triangle_bounds(const mesh *m, size_t i) {
    vec3 p0, p1, p2;
    mesh_triangle_positions(m, i, &p0, &p1, &p2);
    return tri_bounds(p0, p1, p2);
}

/// Watertight test of triangle i against the ray constants tr (tri_ray_make) with tmin < t < tmax.
static inline bool mesh_intersect_triangle(const mesh *m, size_t i, const tri_ray *tr, float tmin, float tmax,
                                           tri_hit *h) {
    vec3 p0, p1, p2;
    mesh_triangle_positions(m, i, &p0, &p1, &p2);
    return tri_intersect(tr, p0, p1, p2, tmin, tmax, h);
}

#endif
