// accel.h — closest-hit and any-hit queries over geometry arrays (brute force or a BVH). Built from the one
// geometry value (geometry/geometry.h: plain arrays of spheres, quads, meshes and instances), never from an
// application's scene, as the build options say (accel_build_options).
#ifndef GLINT_ACCEL_H
#define GLINT_ACCEL_H

#include "core/status.h"
#include "core/vec.h"
#include "geometry/geometry.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

/// Which structure answers the queries: the 8-wide SIMD BVH, the binary BVH, or none (every primitive tested).
typedef enum accel_kind { ACCEL_BVH, ACCEL_BVH2, ACCEL_NONE } accel_kind;
enum { ACCEL_KIND_COUNT = ACCEL_NONE + 1 };
/// Their names, in order ("bvh", "bvh2", "none"): scene files, --accel, checkpoints and traces say these.
extern const char *const accel_kind_names[ACCEL_KIND_COUNT];

/// How a structure is built, apart from what it is built over (geometry_arrays): handed by pointer to
/// accel_build and on to bvh_build, never copied field by field. Zero everywhere: the defaults.
typedef struct accel_build_options {
    const atomic_int *stop;  ///< nonzero once a stop is requested: the build gives up (NULL: never)
    int threads;             ///< threads that build the BVHs (the same BVHs for any number); 0: all online CPUs
    bool no_presplit;        ///< the wide BVHs keep long, slanted triangles whole (tri_split.h; "presplit": false)
    bool no_spatial;         ///< the wide BVHs split only between whole primitives (bvh_spatial.h; "spatial_splits": false)
    size_t parallel_min;     ///< (tests) fewest primitives of a range split by all threads together; 0: the default
    size_t stream_min_bytes; ///< (tests) smallest world BVH (in bytes) for accel_streams; 0: ACCEL_STREAM_MIN_BYTES
    size_t interleave_min_bytes; ///< (tests) the same for accel_interleaves; 0: ACCEL_INTERLEAVE_MIN_BYTES
} accel_build_options;

/// Kinds of primitive a hit can be on.
typedef enum hit_kind { HIT_SPHERE = 0, HIT_QUAD = 1, HIT_TRIANGLE = 2, HIT_MOVING_SPHERE = 3 } hit_kind;

/// No instance: the primitive is in world space.
#define HIT_NO_INSTANCE 0xffffffffu

/// The result of a closest-hit query: distance along the ray and which primitive.
typedef struct hit {
    float t;
    uint32_t prim;     ///< index into the input's array of `kind` (spheres, quads, moving spheres; triangles of the
                       ///< instance's mesh)
    uint32_t kind;     ///< hit_kind
    uint32_t instance; ///< instance the primitive belongs to, or HIT_NO_INSTANCE
    float b1, b2;      ///< triangle barycentrics of vertices 1 and 2; quad (alpha, beta)
} hit;

/// Size of the structure: inner nodes (wide nodes for `bvh`), leaves, levels counting the leaves, build time.
typedef struct accel_stats {
    uint64_t nodes, leaves, depth;
    double build_seconds;
} accel_stats;

/// The acceleration structure of a scene (opaque): immutable once built, shared by every thread.
typedef struct accel accel;

/// Builds a structure of the given kind over g's primitives as opt says (NULL: the defaults). The arrays, not
/// copied, must outlive it; the value *g and its list of meshes are copied, so they may go once it returns. NULL,
/// with a message in *err, when out of memory or stopped (opt->stop).
accel *accel_build(const geometry_arrays *g, accel_kind kind, const accel_build_options *opt, glint_error *err);
/// Frees the structure (NULL is allowed).
void accel_free(accel *a);
/// Tree statistics and build time, for the statistics line.
void accel_get_stats(const accel *a, accel_stats *out);

/// Nearest hit with r->tmin < t < r->tmax, moving primitives where they are at r->time; false when the ray escapes.
bool accel_intersect(const accel *a, const ray *r, hit *h);
/// Rays accel_intersect_stream traces together at most.
#define ACCEL_STREAM 64
/// Smallest world BVH, in bytes of nodes and leaves, for which a caller gains by keeping many paths in flight and
/// gathering their rays for accel_intersect_stream: shading one path's hit while the corners of the next hits are
/// fetched hides the wait for them. Measured with the rays traced one by one (docs/benchmarks.md, "2026-11-27,
/// seventh session"): a 10k-triangle bunny (0.6 MB) 0.993, the bunny (4 MB) 1.034.
#define ACCEL_STREAM_MIN_BYTES ((size_t)2 << 20)
/// Smallest world BVH whose stream rays are traversed together, a step of each in turn so that one ray's waits for
/// memory overlap the others' work; a smaller tree stays close enough in the caches that each ray alone is faster.
/// Against one by one: 278k-triangle bunny (16.7 MB) 0.968, 500k (30 MB) 1.017, 1.1M (62 MB) 1.111.
#define ACCEL_INTERLEAVE_MIN_BYTES ((size_t)24 << 20)
/// Closest hits of n <= ACCEL_STREAM rays, the same as accel_intersect ray by ray: found[i] says whether rays[i]
/// hit, and hits[i] is then its hit. Traversed together where accel_interleaves, else one by one.
void accel_intersect_stream(const accel *a, int n, const ray *rays, hit *hits, bool *found);
/// Whether a caller gains by gathering rays for accel_intersect_stream: a wide BVH of triangles, quads and
/// instances (not only spheres, none of them huge) of at least accel_build_options.stream_min_bytes (by default
/// ACCEL_STREAM_MIN_BYTES). Else it traces them one by one.
bool accel_streams(const accel *a);
/// Whether accel_intersect_stream traverses its rays together: accel_streams' BVH of at least
/// accel_build_options.interleave_min_bytes (by default ACCEL_INTERLEAVE_MIN_BYTES).
bool accel_interleaves(const accel *a);
/// Most rays accel_intersect_coherent takes at once.
enum { ACCEL_COHERENT = 16 };
/// Closest hits of n <= ACCEL_COHERENT rays that start close together and point alike (a pixel's camera rays):
/// traversed as one packet where accel_coherent, else one by one; the same hits as accel_intersect either way.
void accel_intersect_coherent(const accel *a, int n, const ray *rays, hit *hits, bool *found);
/// Whether accel_intersect_coherent traces its rays as a packet (a BVH of triangles and quads only).
bool accel_coherent(const accel *a);
/// Whether anything lies on the ray with r->tmin < t < r->tmax (for shadow rays).
bool accel_occluded(const accel *a, const ray *r);
/// What blocked a path's last shadow ray (accel_occluded_hinted), for its next one: ACCEL_NO_OCCLUDER to start.
#define ACCEL_NO_OCCLUDER 0xffffffffu
/// accel_occluded for a path's next shadow ray, testing first what blocked its last one (*occluder, updated by the
/// wide BVH; the others leave it): the same answer, found in one leaf test where the same object blocks again (a
/// path scattering inside a glass ball).
bool accel_occluded_hinted(const accel *a, const ray *r, uint32_t *occluder);

#endif
