// bvh_kernel.h — the scalar pieces every traversal shares (private to src/accel): the ray prepared for slab
// tests, the lazily made triangle-test constants, and the rule that keeps the better of two hits.
#ifndef GLINT_BVH_KERNEL_H
#define GLINT_BVH_KERNEL_H

#include "accel/bvh.h"

#include <math.h>
#include <string.h>

// Widening of every box's exit distance, so that float rounding of the slab test (under 2^-22 of t, bvh_gather.c)
// never culls a box the ray touches; absolute errors are covered by the boxes' padding (sphere_box, box_padded). So
// many units in the last place, added to the exit's bits: between 2^-20 and 2^-19 of it, and an integer addition,
// where a multiplication by 1 + 2^-20 had stood on the SIMD box test's longest path (the engine 1.012, the Cornell
// box 1.021). Integer order is float order on the distances compared there, non-negative (every ray has tmin >= 0,
// so a box is entered at or after 0) or an empty slot's positive NaN; a negative exit (a box behind the ray) stays
// below every entry. A closest-hit query widens the exit after the cap by the best hit so far (and keeps popped
// subtrees by the like rule, SLAB_FAR_SCALE): a box that holds a hit at the best hit's very distance may win the
// tie (bvh_better). An any-hit query caps after widening: a hit at its tmax does not count, and a shadow ray would
// otherwise test the light it ends at.
enum { SLAB_FAR_ULPS = 16 };
/// The popped subtrees' widening (slab_keeps): relative, since the best hit's distance may be infinite.
static const float SLAB_FAR_SCALE = 1.0f + 0x1p-20f;
// Direction components smaller than this are replaced by it (with their sign): finite inverses.
static const float DIR_EPSILON = 1e-20f;

/// Stack entry: a node or leaf reference and the distance at which the ray enters its box.
typedef struct stack_entry {
    uint32_t ref;
    float t;
} stack_entry;

enum { WIDE_STACK = BVH_MAX_DEPTH * (BVH_WIDTH - 1) + 1, BIN_STACK = BVH_MAX_DEPTH + 1 };

// A ray with a NaN coordinate hits nothing (as in sphere_intersect); rejecting it up front also keeps
// NaN out of the box tests, where min/max would turn it into "every box is hit".
static inline bool ray_is_nan(const ray *r) {
    return isnan(r->o.x) || isnan(r->o.y) || isnan(r->o.z) || isnan(r->d.x) || isnan(r->d.y) || isnan(r->d.z);
}

/// A ray prepared for box tests: t on axis k is box * inv[k] + noi[k] (one FMA); near/far pick the box
/// row (box[k] lower, box[3 + k] upper) the ray enters and leaves by.
typedef struct trav_ray {
    const ray *r;
    float inv[3], noi[3];
    int near[3], far[3];
} trav_ray;

static inline float clamp_dir(float d) { return fabsf(d) < DIR_EPSILON ? copysignf(DIR_EPSILON, d) : d; }

static inline trav_ray trav_setup(const ray *r) {
    trav_ray tr;
    tr.r = r;
    const float o[3] = {r->o.x, r->o.y, r->o.z}, d[3] = {r->d.x, r->d.y, r->d.z};
    for (int k = 0; k < 3; k++) {
        float inv = 1.0f / clamp_dir(d[k]);
        tr.inv[k] = inv;
        tr.noi[k] = -(o[k] * inv);
        tr.near[k] = inv < 0.0f ? 3 + k : k;
        tr.far[k] = inv < 0.0f ? k : 3 + k;
    }
    return tr;
}

// t of a box plane: one fused multiply-add (b - o) / d = b * (1/d) - o * (1/d).
static inline float slab_t(float b, float inv, float noi) {
#if defined(__FMA__) || defined(FP_FAST_FMAF)
    return fmaf(b, inv, noi);
#else
    return b * inv + noi; // without FMA hardware fmaf is a slow library call; the box test is conservative anyway
#endif
}

// max/min with the operand order of SSE maxps/minps, so the scalar and SIMD paths agree bit for bit.
static inline float max_sse(float a, float b) { return a > b ? a : b; }
static inline float min_sse(float a, float b) { return a < b ? a : b; }

// A box's exit distance tf as the box tests compare it, widened by SLAB_FAR_ULPS (its bits plus that, as the SIMD test
// adds them) after the cap tlimit where ties count (`ties`: a closest-hit query), before it otherwise. What is
// widened is finite: the cap may be infinite (no hit yet), but a box's exit is under 2^100 (finite boxes, inverse
// directions at most 1e20).
static inline float slab_exit(float tf, float tlimit, bool ties) {
    if (ties) tf = min_sse(tf, tlimit);
    uint32_t bits;
    memcpy(&bits, &tf, sizeof bits);
    bits += SLAB_FAR_ULPS;
    memcpy(&tf, &bits, sizeof tf);
    return ties ? tf : min_sse(tf, tlimit);
}

// Whether a pending subtree entered at t can still hold the hit a query wants, by the same rule.
static inline bool slab_keeps(float t, float best_t, bool any) { return t <= (any ? best_t : best_t * SLAB_FAR_SCALE); }

/// Per-ray constants of the watertight triangle test, made the first time a quad or triangle needs them.
typedef struct tri_cache {
    bool ready;
    tri_ray tr;
} tri_cache;

static inline const tri_ray *tri_for(tri_cache *c, const ray *r) {
    if (!c->ready) {
        c->tr = tri_ray_make(r);
        c->ready = true;
    }
    return &c->tr;
}

// Keeps candidate c if it beats *best (bvh_better); true when it did.
static inline bool offer(hit *best, hit c) {
    if (!bvh_better(&c, best)) return false;
    *best = c;
    return true;
}

/// How instances are entered: the structure of the BLAS and which traversal path runs it.
typedef enum trav_mode { MODE_WIDE_SIMD, MODE_WIDE_SCALAR, MODE_BINARY } trav_mode;

#endif
