// nee.h — next-event estimation, the path tracer's light sampling at a vertex: towards the point, spot and
// directional lights (no density: no MIS), the emissive quads, triangles and spheres (chosen by the light index,
// integrator/light_sampler.h) and the environment map, each through a shadow ray and the media's transmittance,
// weighted against BSDF or phase-function sampling by the power heuristic (nee_mis_weight, which the path tracer
// also weighs its BSDF samples' hits on lights with).
#ifndef GLINT_NEE_H
#define GLINT_NEE_H

#include "integrator/integrator_common.h"
#include "integrator/light_sampler.h"
#include "integrator/spawn.h"
#include "integrator/surface.h"
#include "material/bsdf.h"

/// Power heuristic weight (beta = 2) of a strategy of density a against one of density b, a > 0: a^2 /
/// (a^2 + b^2), in a form that neither overflows nor divides zero by zero.
static inline float nee_mis_weight(float a, float b) {
    float q = b / a;
    return 1.0f / (1.0f + q * q);
}

/// What next-event estimation needs of the point it lights: a diffuse surface (sf: its normals; in_side = d.ng
/// for the arriving ray d) or a point in a medium (sf NULL: the arriving ray's unit direction d and the phase
/// function's g); at a microfacet material's surface also its BSDF (b, and wo = -d), else b is NULL.
typedef struct nee_vertex {
    const surface *sf;
    float in_side;
    vec3 d;
    float g;
    const bsdf *b;
    vec3 wo;
    bool light_only; ///< (tests) the light samples are not weighted against BSDF sampling
    uint32_t *occluder; ///< what blocked the path's last shadow ray (accel_occluded_hinted), or NULL
} nee_vertex;

/// Direct light from the scene's point, spot and directional lights at vertex vx (spawned at sp), times `weight`:
/// a diffuse surface's albedo (divided by pi here), a BSDF vertex's weight, or a medium's.
vec3 nee_point_lights(const integrator *it, const spawn_point *sp, const nee_vertex *vx, vec3 weight,
                      thread_stats *ts);
/// One sample of the emissive quads, triangles and spheres of light index pl at vertex vx: Le f / pdf times the
/// MIS weight and the transmittance (f: the vertex's nee_density, or its BSDF's f cos); the caller multiplies by
/// the albedo and the path's throughput. Draws the light's choice and its point (RNG_DIM_LIGHT).
vec3 nee_area_lights(const integrator *it, const light_sampler *pl, const nee_vertex *vx, const spawn_point *sp,
                     rng *r, thread_stats *ts);
/// One sample of the environment map (es) at vertex vx, as nee_area_lights (RNG_DIM_ENVIRONMENT).
vec3 nee_environment(const integrator *it, const envmap_sampler *es, const nee_vertex *vx, const spawn_point *sp,
                     rng *r, thread_stats *ts);

#endif
