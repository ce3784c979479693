// material.h — how surfaces scatter and emit light: the book's Lambertian, metal and dielectric, the
// paper's Phong material, emitters, and the microfacet materials (GGX conductor, rough dielectric and the
// glTF 2.0 metallic-roughness `pbr` model). How each scatters is the BSDF interface's (material/bsdf.h).
#ifndef GLINT_MATERIAL_H
#define GLINT_MATERIAL_H

#include "core/vec.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum material_kind {
    MAT_LAMBERTIAN,   ///< ideal diffuse, albedo
    MAT_METAL,        ///< mirror with fuzz, albedo
    MAT_DIELECTRIC,   ///< glass, index of refraction
    MAT_PHONG,        ///< the paper's: colour, specular exponent, reflectivity
    MAT_DIFFUSE_LIGHT, ///< emits `emission`, scatters nothing
    MAT_CONDUCTOR,     ///< GGX rough metal: roughness, anisotropy, complex IOR (eta, k) per channel or an f0 colour
    MAT_ROUGH_DIELECTRIC, ///< GGX rough glass (Walter et al. 2007): ior, roughness, tint of the transmission
    MAT_PBR,           ///< glTF 2.0 metallic-roughness (+ transmission, ior, emissive strength), textures allowed
    MAT_KIND_COUNT     ///< the number of kinds (not a kind)
} material_kind;

/// How a conductor's Fresnel reflectance is computed.
typedef enum conductor_fresnel {
    FRESNEL_COMPLEX_IOR, ///< exact Fresnel equations of a conductor with index eta + i k per channel
    FRESNEL_SCHLICK_F0   ///< Schlick's approximation from the artist's colour f0 at normal incidence
} conductor_fresnel;

typedef struct material {
    material_kind kind;
    vec3 albedo;          ///< Lambertian/metal albedo, Phong colour, dielectric tint (1,1,1 = clear)
    float fuzz;           ///< metal: radius of the random perturbation of the mirror direction, [0,1]
    float ior;            ///< dielectric: index of refraction inside relative to outside
    int specular;         ///< Phong: exponent s; <= 0 means no highlight
    float reflective;     ///< Phong: rfl in [0,1], the mirror weight
    vec3 specular_color;  ///< Phong (colour mode): highlight colour; albedo unless given
    bool has_specular_color;
    vec3 emission;        ///< diffuse_light, pbr: emitted radiance (pbr: glTF emissiveFactor x emissive_strength)
    bool two_sided;       ///< diffuse_light: emit on both sides
    int32_t albedo_texture;   ///< scene texture giving albedo/colour (pbr: base colour) at the hit, or -1: `albedo`
    vec3 base_factor;         ///< pbr: multiplies the base colour texture (glTF's baseColorFactor); (1, 1, 1)
    int32_t emission_texture; ///< scene texture scaling `emission`, or -1
    // The microfacet materials. pbr's base colour is `albedo` (its texture `albedo_texture`), its ior `ior`.
    float roughness;      ///< conductor, rough_dielectric, pbr: perceptual roughness in [0, 1]; GGX alpha = roughness^2
    float anisotropy;     ///< conductor: in [0, 1): alpha_u = alpha / sqrt(1 - 0.9 a), alpha_v = alpha sqrt(1 - 0.9 a)
    conductor_fresnel fresnel; ///< conductor: which of (eta, k) and f0 gives its Fresnel reflectance
    vec3 eta, k;          ///< conductor: complex index of refraction eta + i k per channel (R, G, B)
    vec3 f0;              ///< conductor: reflectance at normal incidence (FRESNEL_SCHLICK_F0)
    float metallic;       ///< pbr: 0 dielectric (specular layer over Lambertian), 1 metal tinted by the base colour
    float transmission;   ///< pbr: KHR_materials_transmission, the share of the dielectric base that is rough glass
    float normal_scale;   ///< pbr: glTF normalTexture.scale, scales the map's x and y
    int32_t metallic_texture;     ///< pbr: texture whose blue channel (linear) scales `metallic`, or -1
    int32_t roughness_texture;    ///< pbr: texture whose green channel (linear) scales `roughness`, or -1
    int32_t transmission_texture; ///< pbr: texture whose red channel (linear) scales `transmission`, or -1
    int32_t normal_texture;       ///< pbr: tangent-space normal map (linear, [0, 1] -> [-1, 1]), or -1
    // Alpha masks (glTF alphaMode MASK): rays pass through the surface where its alpha is below the cutoff.
    float alpha;          ///< coverage factor in [0, 1] (glTF baseColorFactor's A), times alpha_texture's alpha
    int32_t alpha_texture; ///< texture whose alpha plane (texture_alpha) scales `alpha`, or -1
    float alpha_cutoff;   ///< > 0: the surface is cut where alpha x texture alpha < alpha_cutoff; 0: not masked
} material;

/// A material of the given kind with every parameter at its documented default.
material material_default(material_kind kind);
/// The complex index of refraction (*eta, *k) of the conductor preset `name` ("Au", "Ag", "Cu", "Al", "Fe", "Cr",
/// "Pt", "Pb"); false for an unknown name.
bool material_conductor_preset(const char *name, vec3 *eta, vec3 *k);
/// The name of preset i (0, 1, ...), NULL past the last: for messages and documentation.
const char *material_conductor_preset_name(size_t i);
/// Whether m has an alpha mask: hits where material_alpha < alpha_cutoff do not count (integrator/alpha_mask.h).
static inline bool material_masked(const material *m) { return m->alpha_cutoff > 0.0f; }
/// Whether surfaces of m emit light (diffuse_light, or pbr with an emission): the light index samples them.
bool material_emits(const material *m);
/// The scene-file name of a kind ("lambertian", ...).
const char *material_kind_name(material_kind kind);

#endif
