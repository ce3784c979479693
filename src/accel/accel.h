// accel.h — closest-hit and any-hit queries over a scene's primitives (brute force or a BVH).
#ifndef GLINT_ACCEL_H
#define GLINT_ACCEL_H

#include "glint.h"
#include "core/vec.h"

#include <stdbool.h>
#include <stdint.h>

struct glint_scene;

/// Kinds of primitive a hit can be on.
typedef enum hit_kind { HIT_SPHERE = 0, HIT_QUAD = 1, HIT_TRIANGLE = 2 } hit_kind;

/// No instance: the primitive is in world space.
#define HIT_NO_INSTANCE 0xffffffffu

/// The result of a closest-hit query: distance along the ray and which primitive.
typedef struct hit {
    float t;
    uint32_t prim;     ///< index into the scene's array of `kind` (spheres, quads; triangles of the instance's mesh)
    uint32_t kind;     ///< hit_kind
    uint32_t instance; ///< scene instance the primitive belongs to, or HIT_NO_INSTANCE
    float b1, b2;      ///< triangle barycentrics of vertices 1 and 2; quad (alpha, beta)
} hit;

/// Size of the structure: inner nodes (wide nodes for `bvh`), leaves, levels counting the leaves, build time.
typedef struct accel_stats {
    uint64_t nodes, leaves, depth;
    double build_seconds;
} accel_stats;

/// The acceleration structure of a scene (opaque): immutable once built, shared by every thread.
typedef struct accel accel;

/// Builds the structure chosen in the scene's settings over its primitives. NULL on out-of-memory.
accel *accel_build(const struct glint_scene *s, glint_error *err);
/// Frees the structure (NULL is allowed).
void accel_free(accel *a);
/// Tree statistics and build time, for the statistics line.
void accel_get_stats(const accel *a, accel_stats *out);

/// Nearest hit with r->tmin < t < r->tmax; false when the ray escapes.
bool accel_intersect(const accel *a, const ray *r, hit *h);
/// Closest hits of two independent rays at once (faster than two calls: their traversals overlap in the
/// processor); found[i] says whether ray i hit, and h[i] is then its hit.
void accel_intersect2(const accel *a, const ray r[2], hit h[2], bool found[2]);
/// Whether anything lies on the ray with r->tmin < t < r->tmax (for shadow rays).
bool accel_occluded(const accel *a, const ray *r);

#endif
