// bvh_gather.c — the BVH build's input: every primitive's padded box and reference (gathered on the pool for big
// meshes), long, slanted triangles pre-split into pieces with boxes of their own (tri_split.h), the huge spheres
// set apart for the wide BVH, and the references made in place of the input.
#include "accel/bvh_gather.h"
#include "accel/tri_split.h"

#include <stdlib.h>

// Padding that keeps a box conservative after float rounding of the centre, radius and the slab test.
static box3 sphere_box(const sphere *s) {
    float r = fabsf(s->radius);
    float m = max2(fabsf(s->center.x), max2(fabsf(s->center.y), fabsf(s->center.z)));
    float pad = (m + r) * 0x1p-19f + 0x1p-100f;
    box3 b = box_empty();
    b.lo[0] = s->center.x - r - pad;
    b.lo[1] = s->center.y - r - pad;
    b.lo[2] = s->center.z - r - pad;
    b.hi[0] = s->center.x + r + pad;
    b.hi[1] = s->center.y + r + pad;
    b.hi[2] = s->center.z + r + pad;
    return b;
}

// Pads a box so that it stays conservative after the float rounding of the slab test: by 2^-19 of its largest
// coordinate on every axis, or (`per_axis`) of each axis's own. The slab test of an axis rounds by about 2^-24 of its
// plane's and the origin's coordinates, and an origin far beyond the plane (|o| > 2 |plane|) makes an error under
// 2^-22 of t, which the exit distance's widening covers (SLAB_FAR_ULPS); so per axis suffices for boxes whose
// corners are exact (a triangle's, a quad's), and a floor's box is then no thicker than its height needs: a ray
// spawned off the floor starts outside it rather than testing it again. Boxes computed with rounding, of
// transformed or clipped geometry, take the largest coordinate.
static box3 box_padded_by(bounds3 bb, bool per_axis) {
    const float lo[3] = {bb.lo.x, bb.lo.y, bb.lo.z}, hi[3] = {bb.hi.x, bb.hi.y, bb.hi.z};
    float m[3], all = 0.0f;
    for (int k = 0; k < 3; k++) {
        m[k] = max2(fabsf(lo[k]), fabsf(hi[k]));
        all = max2(all, m[k]);
    }
    box3 b = box_empty();
    for (int k = 0; k < 3; k++) {
        float pad = (per_axis ? m[k] : all) * 0x1p-19f + 0x1p-100f;
        b.lo[k] = lo[k] - pad;
        b.hi[k] = hi[k] + pad;
    }
    return b;
}

box3 bvh_box_padded(bounds3 bb) { return box_padded_by(bb, false); }
static box3 box_padded_axes(bounds3 bb) { return box_padded_by(bb, true); }

// Object-space bounds of what an instance places.
static bounds3 instance_object_bounds(const bvh_input *in, const instance *inst) {
    if (inst->kind == INSTANCE_SPHERE) {
        const sphere *sp = &in->geometry->instance_spheres[inst->index];
        float r = fabsf(sp->radius);
        return (bounds3){v3_sub(sp->center, v3s(r)), v3_add(sp->center, v3s(r))};
    }
    return in->blas[inst->index].bounds;
}

// The build input of every primitive: kind, index, padded box, centroid.
/// Triangles whose boxes one pool item gathers.
enum { GATHER_PER_ITEM = 16384 };

/// The boxes of a mesh's triangles, gathered by the pool in runs (each into its own places of prims).
typedef struct gather_job {
    const mesh *m;
    build_prim *prims;
    uint32_t owner; ///< prim_ref.instance of every triangle
    size_t per_item;
    bool split; ///< the mesh is one to pre-split (tri_split_mesh_wants): each triangle's levels are found
    box3 *item_box; ///< item_box[i]: the box of item i's triangles (NULL: not wanted)
} gather_job;

static void gather_triangles_run(void *ctx, size_t item) {
    const gather_job *job = ctx;
    size_t begin = item * job->per_item, count = job->m->triangle_count;
    size_t end = begin + job->per_item < count ? begin + job->per_item : count;
    box3 all = box_empty();
    for (size_t k = begin; k < end; k++) {
        vec3 p[3];
        mesh_triangle_positions(job->m, k, &p[0], &p[1], &p[2]);
        job->prims[k].box = box_padded_axes(bounds3_add(bounds3_add(bounds3_add(bounds3_empty(), p[0]), p[1]), p[2]));
        job->prims[k].split_levels = job->split ? (uint32_t)tri_split_levels(p[0], p[1], p[2]) : 0;
        job->prims[k].ref = (prim_ref){.kind = PRIM_TRIANGLE, .index = (uint32_t)k, .instance = job->owner & PRIM_NO_INSTANCE};
        box_grow(&all, &job->prims[k].box);
    }
    if (job->item_box) job->item_box[item] = all;
}

// Gathers the triangles of m into prims[0, triangle_count), on the pool's threads when there is one, and grows
// *all by their boxes (as one pass in index order would: each item's box, grown in item order).
static void gather_triangles(thread_pool *pool, const mesh *m, uint32_t owner, build_prim *prims, box3 *all) {
    size_t items = (m->triangle_count + GATHER_PER_ITEM - 1) / GATHER_PER_ITEM;
    gather_job job = {m, prims, owner, GATHER_PER_ITEM, tri_split_mesh_wants(m), malloc(items * sizeof(box3))};
    if (pool) thread_pool_run(pool, items, gather_triangles_run, &job);
    else
        for (size_t i = 0; i < items; i++) gather_triangles_run(&job, i);
    if (job.item_box)
        for (size_t i = 0; i < items; i++) box_grow(all, &job.item_box[i]);
    else // no memory for the items' boxes: a pass of its own
        for (size_t k = 0; k < m->triangle_count; k++) box_grow(all, &prims[k].box);
    free(job.item_box);
}

// Gathers the primitives of in into prims (returning how many), with the box of them all in *all and whether they
// are all triangles and quads (triangle packets) in *triangles_only.
size_t bvh_gather_prims(const bvh_input *in, build_prim *prims, thread_pool *pool, box3 *all, bool *triangles_only) {
    const geometry_arrays *g = in->geometry;
    size_t n = 0;
    const uint32_t none = PRIM_NO_INSTANCE;
    *all = box_empty();
    *triangles_only = g->sphere_count == 0 && g->moving_sphere_count == 0;
    for (size_t i = 0; i < g->sphere_count; i++) {
        prims[n].box = sphere_box(&g->spheres[i]);
        prims[n].ref = (prim_ref){.kind = PRIM_SPHERE, .index = (uint32_t)i, .instance = none};
        box_grow(all, &prims[n].box);
        n++;
    }
    for (size_t i = 0; i < g->quad_count; i++) {
        prims[n].box = box_padded_axes(quad_bounds(&g->quads[i]));
        prims[n].ref = (prim_ref){.kind = PRIM_QUAD, .index = (uint32_t)i, .instance = none};
        box_grow(all, &prims[n].box);
        n++;
    }
    if (in->mesh) {
        gather_triangles(pool, in->mesh, none, &prims[n], all);
        n += in->mesh->triangle_count;
    }
    for (size_t i = 0; i < g->instance_count; i++) {
        const instance *inst = &g->instances[i];
        if (in->flat && in->flat[i]) { // its triangles in world space, each a primitive of this BVH
            gather_triangles(pool, in->flat[i], (uint32_t)i & PRIM_NO_INSTANCE, &prims[n], all);
            n += in->flat[i]->triangle_count;
            continue;
        }
        bounds3 ob = instance_object_bounds(in, inst);
        if (bounds3_is_empty(ob)) continue; // an instance of an empty mesh: nothing to hit
        if (inst->motion) { // bounded over the whole shutter, and tested at each ray's time
            prims[n].box = bvh_box_padded(motion_bounds(&g->motions[inst->motion - 1], ob, g->time0, g->time1));
            prims[n].ref = (prim_ref){.kind = PRIM_MOVING_INSTANCE, .index = (uint32_t)i, .instance = none};
        } else {
            prims[n].box = bvh_box_padded(mat4_apply_bounds(&inst->xf.m, ob));
            prims[n].ref = (prim_ref){.kind = PRIM_INSTANCE, .index = (uint32_t)i, .instance = none};
        }
        box_grow(all, &prims[n].box);
        *triangles_only = false;
        n++;
    }
    for (size_t i = 0; i < g->moving_sphere_count; i++) {
        // A centre moving on a line sweeps the segment between its ends: the two end boxes hold the sweep.
        const moving_sphere *ms = &g->moving_spheres[i];
        sphere a = moving_sphere_at(ms, g->time0), b = moving_sphere_at(ms, g->time1);
        prims[n].box = sphere_box(&a);
        box3 bb = sphere_box(&b);
        box_grow(&prims[n].box, &bb);
        prims[n].ref = (prim_ref){.kind = PRIM_MOVING_SPHERE, .index = (uint32_t)i, .instance = none};
        box_grow(all, &prims[n].box);
        n++;
    }
    return n;
}

/* ------------------------------------------------------------------------------------------------ */
/* Pre-splitting long, slanted triangles (tri_split.h)                                                */

/// Primitives whose triangles one pool item looks at for pre-splitting.
enum { SPLIT_PER_ITEM = 16384 };

typedef struct split_job {
    const bvh_input *in;
    build_prim *prims;
    size_t n;     ///< primitives gathered; the extra pieces go after them
    size_t items;
    size_t (*levels)[TRI_SPLIT_MAX_LEVELS + 1]; ///< levels[item][l]: the item's triangles asking for l levels
    size_t *first; ///< first[item]: where the item's extra pieces start, after n
} split_job;

void bvh_prim_triangle(const bvh_input *in, prim_ref r, vec3 p[3]) {
    uint32_t owner = prim_ref_instance(r);
    const mesh *m = owner == HIT_NO_INSTANCE ? in->mesh : in->flat[owner];
    mesh_triangle_positions(m, r.index, &p[0], &p[1], &p[2]);
}

static void split_count_run(void *ctx, size_t item) {
    const split_job *job = ctx;
    size_t begin = item * SPLIT_PER_ITEM, end = begin + SPLIT_PER_ITEM < job->n ? begin + SPLIT_PER_ITEM : job->n;
    for (size_t k = begin; k < end; k++)
        if (job->prims[k].ref.kind == PRIM_TRIANGLE) job->levels[item][job->prims[k].split_levels]++;
}

// The pieces beyond the first of the triangles counted in levels.
static size_t split_extra(const size_t levels[TRI_SPLIT_MAX_LEVELS + 1]) {
    size_t extra = 0;
    for (int l = 1; l <= TRI_SPLIT_MAX_LEVELS; l++) extra += levels[l] * (((size_t)1 << l) - 1);
    return extra;
}

static void split_place_run(void *ctx, size_t item) {
    const split_job *job = ctx;
    if (split_extra(job->levels[item]) == 0) return;
    size_t begin = item * SPLIT_PER_ITEM, end = begin + SPLIT_PER_ITEM < job->n ? begin + SPLIT_PER_ITEM : job->n;
    size_t at = job->n + job->first[item];
    for (size_t k = begin; k < end; k++) {
        if (job->prims[k].ref.kind != PRIM_TRIANGLE || job->prims[k].split_levels == 0) continue;
        int levels = (int)job->prims[k].split_levels;
        vec3 p[3];
        bvh_prim_triangle(job->in, job->prims[k].ref, p);
        bounds3 piece[1 << TRI_SPLIT_MAX_LEVELS];
        int count = tri_split_bounds(p[0], p[1], p[2], levels, piece);
        if (count == 0) continue; // cannot happen for a triangle that asks for levels; keep its whole box
        job->prims[k].box = bvh_box_padded(piece[0]);
        // Every piece counted has its place; a piece found empty (never for a real triangle) repeats the first.
        for (int j = 1; j < 1 << levels; j++)
            job->prims[at++] = (build_prim){bvh_box_padded(piece[j < count ? j : 0]), job->prims[k].ref, 0};
    }
}

// Splits the long, slanted triangles among (*prims)[0, n) into pieces, each a reference to its triangle with the
// box of its part (tri_split.h), the extra pieces appended in order: the same array for any number of threads.
// Returns the new count; n when nothing asks to be split or there is no memory for it (the tree is correct either way).
size_t bvh_presplit(const bvh_input *in, build_prim **prims, size_t n, thread_pool *pool) {
    split_job job = {.in = in, .prims = *prims, .n = n, .items = (n + SPLIT_PER_ITEM - 1) / SPLIT_PER_ITEM};
    job.levels = calloc(job.items, sizeof *job.levels);
    job.first = malloc(job.items * sizeof *job.first);
    size_t extra = 0;
    if (!job.levels || !job.first) goto done;
    if (pool) thread_pool_run(pool, job.items, split_count_run, &job);
    else
        for (size_t i = 0; i < job.items; i++) split_count_run(&job, i);
    for (size_t i = 0; i < job.items; i++) {
        job.first[i] = extra;
        extra += split_extra(job.levels[i]);
    }
    // At most 1 << TRI_SPLIT_MAX_LEVELS references a triangle; nothing to split, or no room: the whole boxes.
    if (extra == 0 || n + extra >= BVH_LEAF / 2) {
        extra = 0;
        goto done;
    }
    build_prim *grown = realloc(*prims, (n + extra) * sizeof *grown);
    if (!grown) {
        extra = 0;
        goto done;
    }
    *prims = job.prims = grown;
    if (pool) thread_pool_run(pool, job.items, split_place_run, &job);
    else
        for (size_t i = 0; i < job.items; i++) split_place_run(&job, i);
done:
    free(job.levels);
    free(job.first);
    return n + extra;
}

// A sphere whose box is at least this fraction of the scene's (by surface area) is not put in the wide tree but
// tested after it, against the tree's nearest hit: nearly every ray enters its box anyway (the book's ground
// of radius 1000, whose box is the scene's), and a test without the traversal's branches costs less than
// the tree step that would reach it (+2% on rtiow-final; tested before the tree, to shorten the ray, it
// measured -2.5%). At most one packet of them.
static const float FRONT_AREA_FRACTION = 0.5f;

// Moves the huge spheres (FRONT_AREA_FRACTION) to the end of prims, keeping the others' order; returns how
// many there are.
// `all` is the box of all of them.
size_t bvh_split_front(build_prim *prims, size_t n, const box3 *all) {
    float limit = FRONT_AREA_FRACTION * box_half_area(all);
    size_t front = 0;
    for (size_t i = 0; i < n && front < BVH_PACKET; i++)
        front += prims[i].ref.kind == PRIM_SPHERE && box_half_area(&prims[i].box) >= limit;
    if (front == 0) return 0;
    build_prim *tmp = malloc(front * sizeof *tmp);
    if (!tmp) return 0; // the tree can hold them as well
    size_t kept = 0, moved = 0;
    for (size_t i = 0; i < n; i++) {
        bool huge = moved < front && prims[i].ref.kind == PRIM_SPHERE && box_half_area(&prims[i].box) >= limit;
        if (huge) tmp[moved++] = prims[i];
        else prims[kept++] = prims[i];
    }
    memcpy(&prims[kept], tmp, front * sizeof *tmp);
    free(tmp);
    return front;
}

// Moves every primitive's reference to the front of the array, in order, and gives the rest back: the
// references take the place of the build input, so that the two are never held at once.
prim_ref *bvh_refs_in_place(build_prim *prims, size_t n) {
    prim_ref *refs = (prim_ref *)(void *)prims;
    for (size_t i = 0; i < n; i++) { // refs[i] lies within prims[0..i], which are read already
        prim_ref r;
        memcpy(&r, &prims[i].ref, sizeof r);
        memcpy(&refs[i], &r, sizeof r);
    }
    prim_ref *fit = realloc(refs, n * sizeof *fit);
    return fit ? fit : refs;
}
