// material.c — defaults and names of materials, and how each scatters in the path tracer (mat_scatter).
#include "material/material.h"
#include "core/sampling.h"
#include "material/scatter.h"

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

// Scattering in the path tracer (declared in material/scatter.h): one random decision per event, the
// throughput weight computed so that its expectation is the BSDF's reflectance.
bool mat_scatter(const material *m, vec3 albedo, vec3 d, vec3 n, bool front, rng *r, scatter_event *ev) {
    ev->diffuse = false;
    ev->transmitted = false;
    switch (m->kind) {
    case MAT_LAMBERTIAN:
        ev->dir = mat_lambertian_dir(n, sample_sphere_uniform(r));
        ev->weight = albedo; // (albedo / pi) cos / (cos / pi)
        ev->diffuse = true;
        return true;
    case MAT_METAL:
        ev->weight = albedo;
        return mat_metal_dir(d, n, m->fuzz, sample_sphere_uniform(r), &ev->dir);
    case MAT_DIELECTRIC: {
        bool reflected;
        float eta = front ? 1.0f / m->ior : m->ior;
        ev->dir = mat_dielectric_dir(d, n, eta, rng_float(r), &reflected);
        ev->transmitted = !reflected;
        ev->weight = albedo; // the tint; (1,1,1) is clear glass
        return true;
    }
    case MAT_PHONG:
        // The paper's colour blend (1 - rfl) diffuse + rfl mirror, as a random choice of one of the two.
        if (rng_float(r) < m->reflective) {
            ev->dir = v3_reflect(d, n);
            ev->weight = v3s(1.0f);
            return true;
        }
        ev->dir = mat_lambertian_dir(n, sample_sphere_uniform(r));
        ev->weight = albedo;
        ev->diffuse = true;
        return true;
    case MAT_DIFFUSE_LIGHT: return false;
    }
    return false;
}
