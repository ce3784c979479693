// bsdf.h — the one interface to how every material scatters light (pbrt-v4's BxDF: f, Sample_f, PDF, flags):
// bsdf_init looks a material's parameters and textures up at a surface point, and bsdf_eval, bsdf_pdf and
// bsdf_sample answer for every kind. The dispatch on the material kind lives here and in bsdf.c only.
//
// Conventions: directions are world-space unit vectors pointing away from the surface; wo towards where the
// path came from, wi where it goes (or towards a light). bsdf_eval is f(wo, wi) without the cosine;
// bsdf_sample's weight is f |cos(wi)| / pdf. Delta lobes (mirrors, smooth glass) are never evaluated: their
// samples carry pdf 0 and the flag BSDF_DELTA.
//
// The book's Lambertian, metal and dielectric and the paper's Phong keep their own sampling, consuming random
// numbers exactly as they always have (mat_scatter, material/scatter.h: the path tracer's fast paths call it
// directly); the fuzzed metal's density is that sampling's own (mat_metal_pdf), so that lights can be sampled at
// it with MIS. The microfacet materials (conductor, rough_dielectric, pbr) are GGX lobes with visible-normal
// sampling and energy compensation (bsdf.c, microfacet.h, bsdf_tables.h).
#ifndef GLINT_BSDF_H
#define GLINT_BSDF_H

#include "core/rng.h"
#include "core/vec.h"
#include "material/material.h"
#include "material/scatter.h"
#include "material/texture.h"

#include <stdbool.h>

/// What lobes a BSDF has, or what lobe a sample came from.
typedef enum bsdf_flags {
    BSDF_REFLECTION = 1u,   ///< scatters back to the side it was lit from
    BSDF_TRANSMISSION = 2u, ///< scatters through the surface
    BSDF_DIFFUSE = 4u,      ///< a Lambertian lobe: next-event estimation pays
    BSDF_GLOSSY = 8u,       ///< a microfacet lobe or the book's fuzzed metal: next-event estimation pays, with MIS
    BSDF_DELTA = 16u        ///< a mirror or refraction direction: sampled only
} bsdf_flags;

/// Where a BSDF is set up: the shading frame and what textures need.
typedef struct bsdf_site {
    vec3 n;        ///< unit shading normal on the side of wo
    vec3 tangent;  ///< a direction in the surface (anisotropy's u axis, the normal map's x); zero: any
    vec3 bitangent; ///< the normal map's y direction (with tangent: the UV frame); zero: n x tangent
    float u, v;    ///< texture coordinates
    vec3 p;        ///< the point textures that vary in space are looked up at (surface_texture_point)
    bool front;    ///< the path arrived on the outward side (dielectrics: entering)
} bsdf_site;

/// A material at one surface point: its parameters with textures looked up, and the shading frame.
typedef struct bsdf {
    const material *m;
    vec3 n, t, b;     ///< shading frame: n on the side of wo (normal-mapped where the material has a map)
    vec3 base;        ///< albedo, base colour or tint (textured)
    float ax, ay;     ///< GGX alphas along t and b
    float rough;      ///< the perceptual roughness the albedo tables are indexed by
    float etap;       ///< dielectric lobes: the index of the far side over the near side
    float metallic, transmission; ///< pbr (textured)
    float f0_dielectric; ///< pbr: reflectance of the dielectric layer at normal incidence, ((ior - 1) / (ior + 1))^2
    vec3 ms_metal;    ///< Kulla–Conty colour F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) of the conductor or metal lobe
    vec3 ms_dielectric; ///< the same for pbr's dielectric specular layer
    float e_avg;      ///< E_avg at this roughness
    float layer_avg;  ///< pbr: the hemispherical albedo of the dielectric specular layer's single scattering
    bool front;       ///< arrived on the outward side
    bool compensate;  ///< energy compensation (on; the tests turn it off to see the single-scattering lobes)
    unsigned flags;   ///< the bsdf_flags of its lobes
} bsdf;

/// One sampled direction.
typedef struct bsdf_sample_record {
    vec3 wi;         ///< unit direction
    vec3 weight;     ///< f |cos(wi)| / pdf
    float pdf;       ///< solid-angle density of wi under bsdf_sample (bsdf_pdf); 0 for a delta lobe's sample
    unsigned flags;  ///< the lobe it came from: BSDF_REFLECTION or BSDF_TRANSMISSION, and its kind
} bsdf_sample_record;

/// Sets b up for material m at `site`, looking its textures up in `textures` (the scene's). `albedo` is the
/// material's albedo (base colour) there, mat_albedo's value, which the caller has looked up already.
void bsdf_init(bsdf *b, const material *m, const texture *textures, vec3 albedo, const bsdf_site *site);
/// f(wo, wi) of the non-delta lobes, without the cosine.
vec3 bsdf_eval(const bsdf *b, vec3 wo, vec3 wi);
/// The density with which bsdf_sample draws wi (its non-delta lobes, times their selection probability).
float bsdf_pdf(const bsdf *b, vec3 wo, vec3 wi);
/// Draws a direction from rng r; false when the path is absorbed (or the material only emits).
bool bsdf_sample(const bsdf *b, vec3 wo, rng *r, bsdf_sample_record *s);

/// Whether the path tracer samples lights at this material's surfaces (it has a diffuse or glossy lobe that
/// bsdf_eval answers for). The book's Lambertian and Phong's diffuse lobe are lit by the path tracer's own
/// fast path; this is for the microfacet materials and the book's fuzzed metal.
static inline bool bsdf_has_nee(const bsdf *b) { return (b->flags & (BSDF_DIFFUSE | BSDF_GLOSSY)) != 0; }

/// Whether m is one of the microfacet materials (conductor, rough_dielectric, pbr).
static inline bool material_is_microfacet(const material *m) { return m->kind > MAT_DIFFUSE_LIGHT; }

/// Whether the path tracer scatters m through bsdf_init/bsdf_sample, with light sampling, rather than its fast
/// paths for the book's materials: the microfacet materials, and the book's fuzzed metal in a scene with lights to
/// sample (`lit`; without, its fast path draws the same directions).
static inline bool material_uses_bsdf(const material *m, bool lit) {
    return material_is_microfacet(m) || (lit && m->kind == MAT_METAL && m->fuzz > 0.0f);
}

/// How the Whitted integrators show a material (they trace mirrors and refraction, and light the rest with
/// Phong's local model): a diffuse colour lit by the lights, a colour the mirror ray is weighted by, and a
/// refraction (ior and the colour the refracted ray is weighted by; the reflected one gets 1 - that's Fresnel).
typedef struct bsdf_whitted {
    vec3 diffuse;     ///< colour the local lighting is weighted by
    vec3 mirror;      ///< colour the mirror reflection is weighted by
    bool refracts;    ///< a dielectric: the colour Whitted's glass branch with `tint`
    vec3 tint;
} bsdf_whitted;

/// The Whitted view of a microfacet material at a point arriving at cos_o to the normal (bsdf_init's b): a
/// conductor is a mirror tinted by its Fresnel reflectance, a rough dielectric is smooth glass, and pbr is its
/// diffuse base lit by the lights plus a mirror weighted by its Fresnel reflectance (roughness is ignored, as
/// Whitted ignores the book's fuzz).
bsdf_whitted bsdf_whitted_view(const bsdf *b, float cos_o);

#endif
