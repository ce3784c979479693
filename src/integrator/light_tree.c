// light_tree.c — building the light tree (binned by the surface area orientation heuristic, SAOH) and walking it:
// the importance bound of a node seen from a point, and the choices down to one light.
#include "integrator/light_tree.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const float pi = 3.14159265358979f;

enum {
    BINS = 12,        ///< candidate split planes per axis
    BALANCED_AT = 32, ///< from this depth on, split by count, so that no trail exceeds 64 choices
};

// ---------------------------------------------------------------------------------------------
// Cones of directions: an axis and the cosine of their half-angle (-1: every direction)

typedef struct cone {
    vec3 axis;
    float theta; ///< half-angle; pi: every direction
} cone;

static float clamp1(float x) { return x < -1.0f ? -1.0f : x > 1.0f ? 1.0f : x; }

// The smallest cone (nearly: it is widened a little against rounding) holding both a and b.
static cone cone_union(cone a, cone b) {
    if (a.theta >= pi || b.theta >= pi) return (cone){a.axis, pi};
    float dot = v3_dot(a.axis, b.axis);
    if (dot >= 1.0f && a.theta == b.theta) return a; // the same cone (flat regions of a mesh): no trigonometry
    float td = acosf(clamp1(dot));
    if (fminf(td + b.theta, pi) <= a.theta) return a;
    if (fminf(td + a.theta, pi) <= b.theta) return b;
    float to = 0.5f * (a.theta + td + b.theta) + 1e-3f; // rounding in the rotation below must not leave a child outside
    vec3 k = v3_cross(a.axis, b.axis);
    float k2 = v3_len2(k);
    if (to >= pi || !(k2 > 1e-12f)) return (cone){a.axis, pi};
    k = v3_scale(k, 1.0f / sqrtf(k2));
    // Rodrigues: a's axis turned towards b's by to - theta_a (k is perpendicular to it).
    float r = to - a.theta, c = cosf(r), s = sinf(r);
    vec3 w = v3_add(v3_scale(a.axis, c), v3_scale(v3_cross(k, a.axis), s));
    return (cone){v3_unit(w), to};
}

// The orientation measure of a cone of normals (half-angle theta_o) spreading light over theta_e: the solid angle
// its emission reaches, weighted by cosine (Conty Estevez and Kulla, eq. 1): the SAOH's cost of the orientation.
static float orientation_measure(float to, float te) {
    float tw = fminf(to + te, pi), so = sinf(to), co = cosf(to);
    return 2.0f * pi * (1.0f - co) + 0.5f * pi * (2.0f * tw * so - cosf(to - 2.0f * tw) - 2.0f * to * so + co);
}

// ---------------------------------------------------------------------------------------------
// Importance: an upper bound of what a node's lights can give a point

// cos(max(0, a - b)) from the sines and cosines of a and b.
static float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}

// sin(max(0, a - b)) from the sines and cosines of a and b.
static float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a > cos_b ? 0.0f : sin_a * cos_b - cos_a * sin_b;
}

static float safe_sqrt(float x) { return sqrtf(x > 0.0f ? x : 0.0f); }

// The node's power over the squared distance to p, times the cosine of the smallest angle between a direction
// its cone emits into and the direction to p that its bounds allow; 0 when no light of it can reach p.
static float importance(const light_tree_node *n, vec3 p) {
    vec3 to = v3_sub(p, n->center);
    float d2 = v3_len2(to), r2 = n->radius2;
    float inv_d = d2 > 0.0f ? 1.0f / sqrtf(d2) : 0.0f;
    float cos_w = d2 > 0.0f ? clamp1(v3_dot(n->axis, to) * inv_d) : 1.0f, sin_w = safe_sqrt(1.0f - cos_w * cos_w);
    // The cone the bounding sphere subtends: sin = r / d (none from inside it).
    bool outside = d2 > r2;
    float sin_b = outside ? sqrtf(r2) * inv_d : 0.0f, cos_b = outside ? safe_sqrt(1.0f - sin_b * sin_b) : -1.0f;
    float cos_x = cos_sub_clamped(sin_w, cos_w, n->sin_o, n->cos_o), sin_x = sin_sub_clamped(sin_w, cos_w, n->sin_o, n->cos_o);
    float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
    if (cos_p <= n->cos_e) return 0.0f;
    float v = n->power * cos_p / (outside ? d2 : r2);
    return isfinite(v) ? v : 0.0f;
}

// The probability of the first child of interior node n for p; false when neither child can reach p.
static bool first_child_probability(const light_tree *t, const light_tree_node *n, vec3 p, float *q) {
    float a = importance(&t->nodes[n->child], p), b = importance(&t->nodes[n->child + 1], p);
    if (!(a + b > 0.0f)) return false;
    *q = a / (a + b);
    return true;
}

size_t light_tree_sample(const light_tree *t, vec3 p, float u, float *pmf) {
    if (!t->node_count) return SIZE_MAX;
    const light_tree_node *n = &t->nodes[0];
    float prob = 1.0f;
    while (n->child != UINT32_MAX) {
        float q;
        if (!first_child_probability(t, n, p, &q)) return SIZE_MAX;
        if (u < q) {
            u = fminf(u / q, 0x1.fffffep-1f);
            prob *= q;
            n = &t->nodes[n->child];
        } else {
            u = fminf((u - q) / (1.0f - q), 0x1.fffffep-1f);
            prob *= 1.0f - q;
            n = &t->nodes[n->child + 1];
        }
    }
    *pmf = prob;
    return n->item;
}

float light_tree_pmf(const light_tree *t, vec3 p, size_t item) {
    const light_tree_node *n = &t->nodes[0];
    float prob = 1.0f;
    uint64_t trail = t->trail[item];
    for (int d = 0; d < t->depth[item]; d++) {
        float q;
        if (!first_child_probability(t, n, p, &q)) return 0.0f;
        bool second = (trail >> d) & 1u;
        prob *= second ? 1.0f - q : q;
        n = &t->nodes[n->child + second];
    }
    return prob;
}

// ---------------------------------------------------------------------------------------------
// Building


static vec3 centroid(const light_tree_item *it) { return v3_scale(v3_add(it->bounds.lo, it->bounds.hi), 0.5f); }

static float axis_of(vec3 v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

static float surface_area(bounds3 b) {
    vec3 d = v3_sub(b.hi, b.lo);
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

/// What a set of lights adds up to: their bounds, power, cone, and the widest spread of their emission (theta_e).
typedef struct summary {
    bounds3 bounds;
    float power, theta_e;
    cone dirs;
    bool any;
} summary;

/// A light as the build sees it: its item's cone as angles, computed once.
typedef struct built_item {
    cone dirs;
    float theta_e;
} built_item;

typedef struct keyed keyed;

typedef struct builder {
    const light_tree_item *items;
    const built_item *cones;
    uint32_t *order; ///< the lights of the node being built occupy a contiguous range
    struct keyed *keys; ///< room to sort a range by centroid
    light_tree *t;
} builder;

static void summary_add(summary *s, const light_tree_item *it, const built_item *b) {
    s->dirs = s->any ? cone_union(s->dirs, b->dirs) : b->dirs;
    s->bounds = s->any ? bounds3_union(s->bounds, it->bounds) : it->bounds;
    s->theta_e = s->any ? fmaxf(s->theta_e, b->theta_e) : b->theta_e;
    s->power += it->power;
    s->any = true;
}

static void summary_merge(summary *s, const summary *o) {
    if (!o->any) return;
    if (!s->any) {
        *s = *o;
        return;
    }
    s->dirs = cone_union(s->dirs, o->dirs);
    s->bounds = bounds3_union(s->bounds, o->bounds);
    s->theta_e = fmaxf(s->theta_e, o->theta_e);
    s->power += o->power;
}

static float cost(const summary *s, float kr) {
    return s->power * orientation_measure(s->dirs.theta, s->theta_e) * surface_area(s->bounds) * kr;
}

/// A light and its centroid on one axis, to sort by (qsort's comparison has no argument to carry the axis).
struct keyed {
    float key;
    uint32_t item;
};

// Orders by centroid, then by light (a total order: the same tree every time).
static int by_key(const void *a, const void *b) {
    const keyed *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->item < y->item ? -1 : x->item > y->item;
}

// Builds node `index` over order[begin, end), reached from the root by `trail` (depth choices).
static void build_node(builder *bd, uint32_t index, size_t begin, size_t end, uint64_t trail, int depth) {
    light_tree *t = bd->t;
    summary all;
    memset(&all, 0, sizeof all);
    bounds3 cb = bounds3_empty();
    for (size_t i = begin; i < end; i++) {
        summary_add(&all, &bd->items[bd->order[i]], &bd->cones[bd->order[i]]);
        cb = bounds3_add(cb, centroid(&bd->items[bd->order[i]]));
    }
    light_tree_node *n = &t->nodes[index];
    vec3 center = v3_scale(v3_add(all.bounds.lo, all.bounds.hi), 0.5f);
    float radius2 = 0.25f * v3_len2(v3_sub(all.bounds.hi, all.bounds.lo));
    float cos_o = all.dirs.theta >= pi ? -1.0f : cosf(all.dirs.theta), sin_o = all.dirs.theta >= pi ? 0.0f : sinf(all.dirs.theta);
    *n = (light_tree_node){center, radius2, all.dirs.axis, cos_o, sin_o, cosf(all.theta_e), all.power, UINT32_MAX, 0};
    if (end - begin == 1) {
        uint32_t item = bd->order[begin];
        n->item = item;
        t->trail[item] = trail;
        t->depth[item] = (uint8_t)depth;
        return;
    }
    vec3 ext = v3_sub(cb.hi, cb.lo);
    float max_ext = fmaxf(ext.x, fmaxf(ext.y, ext.z));
    int best_axis = -1, best_bin = 0;
    float best_cost = INFINITY;
    for (int a = 0; a < 3 && depth < BALANCED_AT; a++) {
        float lo = axis_of(cb.lo, a), e = axis_of(ext, a);
        if (!(e > 0.0f)) continue;
        summary bins[BINS], below[BINS];
        memset(bins, 0, sizeof bins);
        memset(below, 0, sizeof below);
        for (size_t i = begin; i < end; i++) {
            const light_tree_item *it = &bd->items[bd->order[i]];
            int b = (int)((axis_of(centroid(it), a) - lo) / e * BINS);
            summary_add(&bins[b < 0 ? 0 : b >= BINS ? BINS - 1 : b], it, &bd->cones[bd->order[i]]);
        }
        float kr = max_ext / e; // long thin boxes split across their length
        for (int b = 0; b < BINS; b++) {
            if (b) below[b] = below[b - 1];
            summary_merge(&below[b], &bins[b]);
        }
        summary above;
        memset(&above, 0, sizeof above);
        for (int b = BINS - 1; b > 0; b--) {
            summary_merge(&above, &bins[b]);
            if (!below[b - 1].any || !above.any) continue;
            float c = cost(&below[b - 1], kr) + cost(&above, kr);
            if (c < best_cost) best_cost = c, best_axis = a, best_bin = b;
        }
    }
    size_t mid;
    if (best_axis >= 0) { // partition at the chosen plane: bins below best_bin first
        float lo = axis_of(cb.lo, best_axis), e = axis_of(ext, best_axis);
        size_t i = begin, j = end;
        while (i < j) {
            int b = (int)((axis_of(centroid(&bd->items[bd->order[i]]), best_axis) - lo) / e * BINS);
            if ((b >= BINS ? BINS - 1 : b) < best_bin) {
                i++;
            } else {
                uint32_t tmp = bd->order[i];
                bd->order[i] = bd->order[--j];
                bd->order[j] = tmp;
            }
        }
        mid = i;
    } else { // no plane separates the centroids, or deep in the tree: halves by count along the longest axis
        int a = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
        keyed *keys = bd->keys;
        for (size_t i = begin; i < end; i++)
            keys[i - begin] = (keyed){axis_of(centroid(&bd->items[bd->order[i]]), a), bd->order[i]};
        qsort(keys, end - begin, sizeof *keys, by_key);
        for (size_t i = begin; i < end; i++) bd->order[i] = keys[i - begin].item;
        mid = begin + (end - begin) / 2;
    }
    uint32_t child = (uint32_t)t->node_count;
    t->node_count += 2;
    n->child = child;
    build_node(bd, child, begin, mid, trail, depth + 1);
    build_node(bd, child + 1, mid, end, trail | (UINT64_C(1) << depth), depth + 1);
}

bool light_tree_build(light_tree *t, const light_tree_item *items, size_t count) {
    memset(t, 0, sizeof *t);
    if (count == 0 || count > UINT32_MAX / 2) return count == 0;
    t->nodes = malloc((2 * count - 1) * sizeof *t->nodes);
    t->trail = malloc(count * sizeof *t->trail);
    t->depth = malloc(count * sizeof *t->depth);
    uint32_t *order = malloc(count * sizeof *order);
    keyed *keys = malloc(count * sizeof *keys);
    built_item *cones = malloc(count * sizeof *cones);
    if (!t->nodes || !t->trail || !t->depth || !order || !keys || !cones) {
        free(order);
        free(keys);
        free(cones);
        light_tree_release(t);
        return false;
    }
    for (size_t i = 0; i < count; i++) {
        order[i] = (uint32_t)i;
        cones[i] = (built_item){{items[i].axis, items[i].cos_o <= -1.0f ? pi : acosf(clamp1(items[i].cos_o))},
                                acosf(clamp1(items[i].cos_e))};
    }
    builder bd = {items, cones, order, keys, t};
    t->node_count = 1;
    build_node(&bd, 0, 0, count, 0, 0);
    free(order);
    free(keys);
    free(cones);
    return true;
}

void light_tree_release(light_tree *t) {
    free(t->nodes);
    free(t->trail);
    free(t->depth);
    memset(t, 0, sizeof *t);
}
