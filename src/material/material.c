// material.c — defaults and names of materials (how each scatters is the BSDF interface's, material/bsdf.h).
#include "material/material.h"

material material_default(material_kind kind) {
    material m = {0};
    m.kind = kind;
    m.albedo = v3s(kind == MAT_DIELECTRIC || kind == MAT_ROUGH_DIELECTRIC ? 1.0f : kind == MAT_PBR ? 0.8f : 0.5f);
    m.fuzz = 0.0f;
    m.ior = 1.5f;
    m.specular = -1;
    m.reflective = 0.0f;
    m.emission = v3s(kind == MAT_PBR ? 0.0f : 1.0f);
    m.two_sided = false;
    m.albedo_texture = -1;
    m.base_factor = v3s(1.0f);
    m.emission_texture = -1;
    // Microfacet defaults: Blender's Principled BSDF's roughness 0.5, a dielectric pbr, aluminium for a conductor.
    m.roughness = 0.5f;
    m.anisotropy = 0.0f;
    m.fresnel = FRESNEL_COMPLEX_IOR;
    m.eta = v3(1.0f, 1.0f, 1.0f); // set from the default preset by the scene reader (material_conductor_preset)
    m.k = v3s(0.0f);
    m.f0 = v3s(1.0f);
    m.metallic = 0.0f;
    m.transmission = 0.0f;
    m.normal_scale = 1.0f;
    m.metallic_texture = m.roughness_texture = m.transmission_texture = m.normal_texture = -1;
    m.alpha = 1.0f;
    m.alpha_texture = -1;
    m.alpha_cutoff = 0.0f; // not masked
    if (kind == MAT_CONDUCTOR) material_conductor_preset("Al", &m.eta, &m.k);
    return m;
}

bool material_emits(const material *m) {
    if (m->kind == MAT_DIFFUSE_LIGHT) return true;
    return m->kind == MAT_PBR && v3_max_comp(m->emission) > 0.0f;
}

// Complex indices of refraction eta + i k of metals at R, G, B-representative wavelengths 650, 550 and 450 nm: the
// measured optical constants of refractiveindex.info (Rakić et al. 1998, Johnson and Christy 1972/74, Palik) at those
// wavelengths, as tabulated in V. Koylazov, "Understanding metalness" (Chaos Group blog, 2014).
static const struct conductor_preset {
    const char *name;
    vec3 eta, k;
} presets[] = {
    {"Ag", {0.15943f, 0.14512f, 0.13547f}, {3.9291f, 3.1900f, 2.3808f}},
    {"Al", {1.3456f, 0.96521f, 0.61722f}, {7.4746f, 6.3995f, 5.3031f}},
    {"Au", {0.18299f, 0.42108f, 1.3734f}, {3.4242f, 2.3459f, 1.7704f}},
    {"Cr", {3.1071f, 3.1812f, 2.3230f}, {3.3314f, 3.3291f, 3.1350f}},
    {"Cu", {0.27105f, 0.67693f, 1.3164f}, {3.6092f, 2.6248f, 2.2921f}},
    {"Fe", {2.9114f, 2.9497f, 2.5845f}, {3.0893f, 2.9318f, 2.7670f}},
    {"Pb", {1.91f, 1.83f, 1.44f}, {3.51f, 3.40f, 3.18f}},
    {"Pt", {2.3757f, 2.0847f, 1.8453f}, {4.2655f, 3.7153f, 3.1365f}},
};

bool material_conductor_preset(const char *name, vec3 *eta, vec3 *k) {
    for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++) {
        const char *a = presets[i].name, *b = name;
        while (*a && *a == *b) a++, b++;
        if (*a == 0 && *b == 0) {
            *eta = presets[i].eta;
            *k = presets[i].k;
            return true;
        }
    }
    return false;
}

const char *material_conductor_preset_name(size_t i) {
    return i < sizeof presets / sizeof presets[0] ? presets[i].name : NULL;
}

const char *material_kind_name(material_kind kind) {
    switch (kind) {
    case MAT_LAMBERTIAN: return "lambertian";
    case MAT_METAL: return "metal";
    case MAT_DIELECTRIC: return "dielectric";
    case MAT_PHONG: return "phong";
    case MAT_DIFFUSE_LIGHT: return "diffuse_light";
    case MAT_CONDUCTOR: return "conductor";
    case MAT_ROUGH_DIELECTRIC: return "rough_dielectric";
    case MAT_PBR: return "pbr";
    case MAT_KIND_COUNT: break;
    }
    return "?";
}
