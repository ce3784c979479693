// bvh_stream.c — closest hits of up to 64 rays through the wide BVH, traced together one step of each ray in turn
// (wide_step, bvh_wide.h): while one ray waits for memory the others work. Each ray makes the steps its single-ray
// traversal makes, so the hits are bvh_intersect's. With AVX2 (BVH_SIMD) only; otherwise the rays go one by one.
#include "accel/bvh_wide.h"

#if BVH_SIMD
/// One ray of a stream in flight, compact: the scalars its registers are broadcast from at each step (about 100
/// bytes where the registers' images take 500), so that the stream's rays stay in the L1 cache beside the nodes
/// and packets they wait for; its best hit so far and where its walk stands. The broadcasts give the registers
/// simd_setup and simd_tri_setup make, bit for bit.
typedef struct stream_ray {
    float inv[3], noi[3]; ///< the box tests' constants (simd_setup's, one lane of each)
    float a, inv_a;       ///< the sphere test's, in a tree with spheres (likewise)
    tri_cache tc;         ///< the triangle test's once made: up front in a tree of triangles, else at the first packet
    hit best;
    walk w;
    bool found;
} stream_ray;

// Readies ray r to walk b from its root with the SIMD kernels (`triangles`: b holds only triangle packets, whose
// constants are made up front); false for a NaN ray, which hits nothing.
static inline bool stream_ray_start(const bvh *b, const ray *r, stream_ray *q, bool triangles) {
    simd_ray sr;
    if (!simd_setup(r, &sr, triangles)) return false;
    for (int a = 0; a < 3; a++) {
        q->inv[a] = _mm256_cvtss_f32(sr.inv[a]);
        q->noi[a] = _mm256_cvtss_f32(sr.noi[a]);
    }
    q->a = triangles ? 0.0f : PK(cvtss_f32)(sr.a);
    q->inv_a = triangles ? 0.0f : PK(cvtss_f32)(sr.inv_a);
    q->tc.ready = false;
    if (triangles) tri_for(&q->tc, r);
    q->best = bvh_no_hit(r);
    q->w = (walk){b->root, 0};
    q->found = false;
    return true;
}

// One traversal step of ray r, its registers broadcast from its compact state q (stream_ray); the triangle test's
// only at a leaf, the one step that reads them (broadcast at every step, they cost engine-2m 3 %: 1.029).
static inline __attribute__((always_inline)) int stream_ray_step(const bvh *b, const ray *r, stream_ray *q,
                                                                 stack_entry *stack, int leaves) {
    simd_ray sr;
    simd_tri st = {.tr = NULL}; // a mixed tree's triangle constants: made at the ray's first triangle packet (q->tc)
    for (int a = 0; a < 3; a++) {
        sr.inv[a] = _mm256_set1_ps(q->inv[a]);
        sr.noi[a] = _mm256_set1_ps(q->noi[a]);
    }
    sr.tmin = PK(broadcast_ss)(&r->tmin);
    if (leaves != LEAVES_TRIANGLES) { // the sphere test's, as simd_setup makes them
        sr.ox = PK(broadcast_ss)(&r->o.x);
        sr.oy = PK(broadcast_ss)(&r->o.y);
        sr.oz = PK(broadcast_ss)(&r->o.z);
        sr.dx = PK(broadcast_ss)(&r->d.x);
        sr.dy = PK(broadcast_ss)(&r->d.y);
        sr.dz = PK(broadcast_ss)(&r->d.z);
        sr.tmax = PK(broadcast_ss)(&r->tmax);
        sr.a = PK(set1_ps)(q->a);
        sr.inv_a = PK(set1_ps)(q->inv_a);
        sr.tmin_nonneg = PK(cmp_ps)(sr.tmin, PK(setzero_ps)(), _CMP_GE_OQ);
    }
    if ((q->w.ref & BVH_LEAF) && (leaves == LEAVES_TRIANGLES || q->tc.ready))
        simd_tri_setup(&q->tc.tr, r->tmin, r->tmax, &st);
    return wide_step(b, r, NULL, &sr, &st, &q->tc, stack, &q->w, &q->best, HIT_NO_INSTANCE, &q->found, false, true,
                     leaves);
}

/// Deepest tree whose rays a stream traces all at once (deeper trees' go in smaller groups), and the stack entries a
/// ray of it may need.
enum { STREAM_DEPTH = 24, STREAM_STACK = STREAM_DEPTH * (BVH_WIDTH - 1) + 1 };

// wide_stream for a group of n rays whose stacks of `stride` entries fit in the group's room.
static inline __attribute__((always_inline)) void wide_stream_group(const bvh *b, int n, const ray *rays, hit *hits,
                                                                    bool *found, int leaves, size_t stride) {
    stream_ray s[BVH_STREAM];
    stack_entry stacks[BVH_STREAM * STREAM_STACK];
    int active[BVH_STREAM], live = 0;
    for (int i = 0; i < n; i++) {
        found[i] = false;
        // No tree, or a NaN ray: nothing to trace.
        if (b->root == BVH_EMPTY || !stream_ray_start(b, &rays[i], &s[i], leaves == LEAVES_TRIANGLES)) continue;
        active[live++] = i;
    }
    while (live > 0) {
        for (int k = 0; k < live;) {
            int i = active[k];
            if (stream_ray_step(b, &rays[i], &s[i], &stacks[(size_t)i * stride], leaves) == STEP_MORE) {
                k++;
                continue;
            }
            found[i] = s[i].found;
            hits[i] = s[i].best;
            active[k] = active[--live]; // done: its place goes to the last ray in flight
        }
    }
}

// Closest hits of n <= BVH_STREAM rays through a wide BVH, one step of each ray in turn: a step ends by
// prefetching the children it will visit, so while one ray waits for memory the others work. Each ray makes the
// same steps in the same order as wide_run alone, so the hits are the same.
static inline __attribute__((always_inline)) void wide_stream(const bvh *b, int n, const ray *rays, hit *hits,
                                                              bool *found, int leaves) {
    // Each ray's stack holds at most BVH_WIDTH - 1 entries per level of the tree: packed that close, the stacks
    // in use share few cache lines. Room for STREAM_DEPTH levels keeps the frame small (a library's caller may
    // render on a thread with a small stack); a deeper tree's rays go in smaller groups.
    size_t stride = b->stats.depth < BVH_MAX_DEPTH ? (size_t)b->stats.depth * (BVH_WIDTH - 1) + 1 : WIDE_STACK;
    size_t group = BVH_STREAM * STREAM_STACK / stride;
    if (group > BVH_STREAM) group = BVH_STREAM;
    for (int first = 0; first < n; first += (int)group) {
        int count = n - first < (int)group ? n - first : (int)group;
        wide_stream_group(b, count, rays + first, hits + first, found + first, leaves, stride);
    }
}

bool bvh_streams(const bvh *b) { return !b->spheres_only && b->front == BVH_EMPTY; }

void bvh_intersect_stream(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    if (!bvh_streams(b)) { // the sphere traversal is tuned for one ray; huge spheres are tested after the tree
        for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
    } else if (b->triangles_only) {
        wide_stream(b, n, rays, hits, found, LEAVES_TRIANGLES);
    } else {
        wide_stream(b, n, rays, hits, found, LEAVES_ANY);
    }
}
#else
bool bvh_streams(const bvh *b) {
    (void)b;
    return false;
}

void bvh_intersect_stream(const bvh *b, int n, const ray *rays, hit *hits, bool *found) {
    for (int i = 0; i < n; i++) found[i] = bvh_intersect(b, &rays[i], &hits[i]);
}
#endif
