// light_sampler.h — the path tracer's index of a scene's emissive quads and mesh triangles for next-event
// estimation: lights chosen in proportion to their power, and the density with which a point was chosen.
#ifndef GLINT_LIGHT_SAMPLER_H
#define GLINT_LIGHT_SAMPLER_H

#include "core/vec.h"
#include "integrator/light_tree.h"
#include "integrator/surface.h"
#include "scene/scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// An emissive triangle of a mesh instance, in world space (placed by the instance's transform at prepare time).
typedef struct tri_light {
    vec3 p0, e1, e2;   ///< corner and the edges to the other two corners
    vec3 n;            ///< unit normal of the world-space triangle, either side (for the area-to-solid-angle factor)
    float area;
    uint32_t instance; ///< scene instance, and the triangle in its mesh: for emission sides and texture coordinates
    uint32_t tri;
    uint32_t material;
} tri_light;

/// What a light of the index is.
typedef enum light_ref_kind { LIGHT_REF_QUAD, LIGHT_REF_TRIANGLE, LIGHT_REF_SPHERE } light_ref_kind;

/// One light of the index: a scene quad, a triangle of tris, or a world-space scene sphere.
typedef struct light_ref {
    uint32_t kind;  ///< a light_ref_kind
    uint32_t index; ///< into s->quads, light_sampler.tris or s->spheres
} light_ref;

/// The scene's emissive quads, mesh triangles and spheres, indexed for next-event estimation (built by
/// light_sampler_build).
typedef struct light_sampler {
    light_ref *lights;      ///< the lights: quads in scene order, triangles by instance and triangle, then spheres
    float *cdf;             ///< cdf[i]: probability of choosing one of lights[0..i]; the last is 1
    float *select_pdf;      ///< per scene quad: probability of choosing it, 0 for a quad that is not a light
    size_t count;           ///< lights
    size_t quad_count;      ///< scene quads when indexed (select_pdf's length)
    size_t quad_lights;     ///< lights that are quads: the first triangle light's entry in lights
    tri_light *tris;        ///< the emissive triangles
    size_t tri_count;
    size_t *tri_base;       ///< per scene instance: its first triangle's entry in tri_select_pdf, or SIZE_MAX
    float *tri_select_pdf;  ///< per triangle of each instance with a tri_base: probability of choosing it, or 0
    size_t instance_count;  ///< scene instances when indexed (tri_base's length)
    float *sphere_select_pdf; ///< per world-space scene sphere: probability of choosing it, 0 when it is no light
    size_t sphere_count;    ///< scene spheres when indexed (sphere_select_pdf's length; 0 when none emits)
    /// With many lights (LIGHT_TREE_MIN_LIGHTS), a light is chosen for each point by the light tree instead of by
    /// power alone; the select arrays above then only say which quads, triangles and spheres are lights.
    light_tree tree;
    uint32_t *quad_light, *sphere_light; ///< with the tree: per scene quad and sphere, its entry in lights
} light_sampler;

/// Lights from which on the light tree chooses them (fewer are chosen by power: the tree's work per choice would
/// cost more than it saves, and the scenes of the books keep their bytes).
enum { LIGHT_TREE_MIN_LIGHTS = 64 };

/// Chooses a light for next-event estimation at point p from xi uniform in [0, 1): its entry in ls->lights, and in
/// *select the probability of that choice; SIZE_MAX when no light can reach p.
size_t light_sampler_choose(const light_sampler *ls, vec3 p, float xi, float *select);

/// Indexes the emissive quads, mesh-instance triangles and world-space spheres of s (spheres placed by
/// instances are left to BSDF sampling), and with `tree` and many of them builds the light tree. An empty sampler (count 0)
/// when nothing emits. False when out of memory (ls is then empty).
bool light_sampler_build(light_sampler *ls, const glint_scene *s, bool tree);
/// Frees what the sampler owns and leaves it empty.
void light_sampler_release(light_sampler *ls);
/// Probability density, per unit solid angle, with which next-event estimation would have chosen the point
/// where a ray from o of unit direction d hit surface sf at distance t; 0 when it is not an indexed light.
float light_sampler_pdf(const light_sampler *ls, const glint_scene *s, const surface *sf, vec3 o, vec3 d, float t);
/// A direction from p towards sphere sp, uniform in the cone of directions the sphere subtends ("The Rest of
/// Your Life", ch. 12), from two uniform numbers a, b: the unit direction *wi, the distance *dist to where it
/// meets the sphere, and the cone's density per unit solid angle *pdf. False when p is not outside the sphere.
bool light_sphere_sample(const sphere *sp, vec3 p, float a, float b, vec3 *wi, float *dist, float *pdf);
/// The density per unit solid angle of light_sphere_sample's directions from p; 0 when p is not outside.
float light_sphere_pdf(const sphere *sp, vec3 p);
/// The density with which light_sphere_sample would draw unit direction wi from p: light_sphere_pdf inside
/// the cone the sphere subtends, 0 outside it.
float light_sphere_pdf_towards(const sphere *sp, vec3 p, vec3 wi);
/// The emitted radiance of triangle light tl at barycentrics (b1, b2), point x, towards unit direction wi.
vec3 light_sampler_tri_emitted(const glint_scene *s, const tri_light *tl, float b1, float b2, vec3 x, vec3 wi);

#endif
