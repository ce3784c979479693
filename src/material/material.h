// material.h — how surfaces scatter and emit light: the book's Lambertian, metal and dielectric, the
// paper's Phong material, and emitters.
#ifndef GLINT_MATERIAL_H
#define GLINT_MATERIAL_H

#include "core/vec.h"

#include <stdbool.h>
#include <stdint.h>

typedef enum material_kind {
    MAT_LAMBERTIAN,   ///< ideal diffuse, albedo
    MAT_METAL,        ///< mirror with fuzz, albedo
    MAT_DIELECTRIC,   ///< glass, index of refraction
    MAT_PHONG,        ///< the paper's: colour, specular exponent, reflectivity
    MAT_DIFFUSE_LIGHT ///< emits `emission`, scatters nothing
} material_kind;

typedef struct material {
    material_kind kind;
    vec3 albedo;          ///< Lambertian/metal albedo, Phong colour, dielectric tint (1,1,1 = clear)
    float fuzz;           ///< metal: radius of the random perturbation of the mirror direction, [0,1]
    float ior;            ///< dielectric: index of refraction inside relative to outside
    int specular;         ///< Phong: exponent s; <= 0 means no highlight
    float reflective;     ///< Phong: rfl in [0,1], the mirror weight
    vec3 specular_color;  ///< Phong (colour mode): highlight colour; albedo unless given
    bool has_specular_color;
    vec3 emission;        ///< diffuse_light: emitted radiance
    bool two_sided;       ///< diffuse_light: emit on both sides
    int32_t albedo_texture;   ///< scene texture giving albedo/colour at the hit, or -1: `albedo`
    int32_t emission_texture; ///< scene texture scaling `emission`, or -1
} material;

/// A material of the given kind with every parameter at its documented default.
material material_default(material_kind kind);
/// The scene-file name of a kind ("lambertian", ...).
const char *material_kind_name(material_kind kind);

#endif
