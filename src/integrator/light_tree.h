// light_tree.h — a bounding volume hierarchy over a scene's lights for choosing one in proportion to how much it
// can light a point (Conty Estevez and Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree
// Splitting"; as Cycles 3.5 and pbrt-v4's BVHLightSampler do): each node bounds its lights' positions, their
// total power and the cone of directions they emit into, and a point descends from the root choosing each child
// in proportion to an upper bound of the light it can receive from it (power over squared distance, times the
// cosine the cones allow). The probability of a choice is a pure function of the point and the light, so that
// sampling and the MIS weights of BSDF hits agree on it exactly (light_tree_pmf walks the same path).
#ifndef GLINT_LIGHT_TREE_H
#define GLINT_LIGHT_TREE_H

#include "core/vec.h"
#include "geometry/transform.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// What the tree knows of one light: where it lies, its power, and the directions it emits into (the normals
/// within an angle theta_o of `axis`, each spreading light over theta_e around it: a flat one-sided emitter has
/// cos_o = 1 and cos_e = 0; a sphere or a two-sided one cos_o = -1).
typedef struct light_tree_item {
    bounds3 bounds;
    float power;
    vec3 axis;
    float cos_o, cos_e;
} light_tree_item;

/// A node: the union of its lights, as the importance bound reads it (its bounds as their bounding sphere).
/// Interior nodes have two children, `child` and `child + 1`; a leaf holds the single light `item`.
typedef struct light_tree_node {
    vec3 center;
    float radius2; ///< the bounding sphere's radius, squared
    vec3 axis;
    float cos_o, sin_o, cos_e, power;
    uint32_t child; ///< first child, or UINT32_MAX for a leaf
    uint32_t item;  ///< a leaf's light
} light_tree_node;

typedef struct light_tree {
    light_tree_node *nodes; ///< nodes[0] is the root
    size_t node_count;
    uint64_t *trail;        ///< per light: the choices from the root to its leaf, bit d set for the second child
    uint8_t *depth;         ///< per light: the length of its trail
} light_tree;

/// Builds the tree over `count` lights (binned by the surface area orientation heuristic); false when out of
/// memory (the tree is then empty). Lights of zero power must be left out.
bool light_tree_build(light_tree *t, const light_tree_item *items, size_t count);
/// Frees the tree and leaves it empty.
void light_tree_release(light_tree *t);
/// Chooses a light for point p from u uniform in [0, 1): its index, and in *pmf the probability of choosing it;
/// SIZE_MAX when no light can reach p.
size_t light_tree_sample(const light_tree *t, vec3 p, float u, float *pmf);
/// The probability that light_tree_sample chooses light `item` for point p.
float light_tree_pmf(const light_tree *t, vec3 p, size_t item);

#endif
