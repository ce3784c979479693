// material.c — defaults and names of materials (how each scatters is mat_scatter, in material/scatter.h).
#include "material/material.h"

material material_default(material_kind kind) {
    material m = {0};
    m.kind = kind;
    m.albedo = v3s(kind == MAT_DIELECTRIC ? 1.0f : 0.5f);
    m.fuzz = 0.0f;
    m.ior = 1.5f;
    m.specular = -1;
    m.reflective = 0.0f;
    m.emission = v3s(1.0f);
    m.two_sided = false;
    m.albedo_texture = -1;
    m.emission_texture = -1;
    return m;
}

const char *material_kind_name(material_kind kind) {
    switch (kind) {
    case MAT_LAMBERTIAN: return "lambertian";
    case MAT_METAL: return "metal";
    case MAT_DIELECTRIC: return "dielectric";
    case MAT_PHONG: return "phong";
    case MAT_DIFFUSE_LIGHT: return "diffuse_light";
    }
    return "?";
}
