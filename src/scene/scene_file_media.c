// scene_file_media.c — the scene file's participating media: objects of type "constant_medium" (book 2's:
// a density and an albedo) and "homogeneous_medium" (sigma_a, sigma_s), each inside a "boundary" (a sphere or
// a box, with an optional transform), with a Henyey–Greenstein "g".
#include "scene/scene_file_common.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char *const sphere_boundary_keys[] = {"type", "center", "radius", "transform", NULL};
static const char *const box_boundary_keys[] = {"type", "min", "max", "transform", NULL};

static const struct boundary_type {
    const char *name;
    const char *const *keys;
} boundary_types[] = {
    {"sphere", sphere_boundary_keys},
    {"box", box_boundary_keys},
};
#define BOUNDARY_TYPES (sizeof boundary_types / sizeof boundary_types[0])

/// Coefficients (density, sigma_a, sigma_s): finite, >= 0, at most MEDIUM_MAX_COEFFICIENT.
static const jr_numspec coefficient = {0.0, MEDIUM_MAX_COEFFICIENT, JR_FLOAT, "a number in [0, 1e30]"};
static const jr_numspec positive_coefficient = {0.0, MEDIUM_MAX_COEFFICIENT, JR_FLOAT | JR_LO_OPEN,
                                                "a number in (0, 1e30]"};
/// Henyey–Greenstein's g: |g| = 1 would be a delta (a ray that never turns, or turns straight back).
static const jr_numspec asymmetry = {-1.0, 1.0, JR_FLOAT | JR_LO_OPEN | JR_HI_OPEN, "a number in (-1, 1)"};

// The required "boundary" of object o into m's shape: a sphere or a box, placed by its own "transform".
static bool read_boundary(sf_loader *ld, const jr_obj *o, medium *m) {
    const jr_member *bm;
    if (!jr_lookup(&ld->r, o, "boundary", true, &bm)) return false;
    char what[160], typed[192];
    snprintf(what, sizeof what, "the boundary of %s", o->what);
    size_t t;
    if (!jr_open_typed(&ld->r, bm->val, what, boundary_types, BOUNDARY_TYPES, sizeof boundary_types[0], &t))
        return false;
    snprintf(typed, sizeof typed, "the boundary (%s) of %s", boundary_types[t].name, o->what);
    jr_obj b;
    if (!jr_open(&ld->r, bm->val, typed, boundary_types[t].keys, &b)) return false;
    bounds3 box;
    if (t == 0) {
        m->shape = MEDIUM_SPHERE;
        if (!jr_read_vec3(&ld->r, &b, "center", true, &JR_FINITE, &m->center) ||
            !jr_read_float(&ld->r, &b, "radius", true, &JR_POSITIVE, &m->radius))
            return false;
        box = (bounds3){v3_sub(m->center, v3s(m->radius)), v3_add(m->center, v3s(m->radius))};
    } else {
        m->shape = MEDIUM_BOX;
        if (!jr_read_vec3(&ld->r, &b, "min", true, &JR_FINITE, &m->lo) ||
            !jr_read_vec3(&ld->r, &b, "max", true, &JR_FINITE, &m->hi))
            return false;
        for (int k = 0; k < 3; k++) {
            float lo = v3_comp(m->lo, k), hi = v3_comp(m->hi, k);
            if (!(lo < hi))
                return jr_fail_at(&ld->r, jr_member_offset(&ld->r, &b, "max"),
                                  "\"max\" must be greater than \"min\" in every coordinate, but \"max\"[%d] = %g <= "
                                  "\"min\"[%d] = %g",
                                  k, (double)hi, k, (double)lo);
        }
        box = (bounds3){m->lo, m->hi};
    }
    transform xf;
    bool moved;
    if (!sf_read_transform(ld, &b, &xf, &moved)) return false;
    m->transformed = moved;
    m->to_object = xf.inv;
    if (moved) box = mat4_apply_bounds(&xf.m, box);
    return sf_check_extent(ld, jr_member_offset(&ld->r, &b, moved ? "transform" : t == 0 ? "center" : "max"),
                           moved ? "the transformed boundary" : "the boundary", box);
}

static bool add_medium(sf_loader *ld, medium m) { return scene_add_medium(ld->scene, m) || sf_fail_oom(ld); }

// Book 2's constant_medium: extinction `density` in every channel, scattering density * albedo (a colour or
// a texture looked up at the scattering point), an isotropic phase function unless "g" says otherwise.
bool sf_read_constant_medium(sf_loader *ld, const jr_obj *o, const char *what) {
    (void)what;
    medium m = {0};
    m.albedo_texture = -1;
    vec3 albedo = v3s(1.0f);
    float density;
    if (!read_boundary(ld, o, &m) || !jr_read_float(&ld->r, o, "density", true, &positive_coefficient, &density) ||
        !sf_read_color_or_texture(ld, o, "albedo", &JR_UNIT, &albedo, &m.albedo_texture) ||
        !jr_read_float(&ld->r, o, "g", false, &asymmetry, &m.g))
        return false;
    m.sigma_t = v3s(density);
    m.sigma_s = v3_scale(albedo, density);
    return add_medium(ld, m);
}

// A homogeneous medium given by its absorption and scattering coefficients, per channel.
bool sf_read_homogeneous_medium(sf_loader *ld, const jr_obj *o, const char *what) {
    (void)what;
    medium m = {0};
    m.albedo_texture = -1;
    vec3 sigma_a = v3s(0.0f);
    if (!read_boundary(ld, o, &m) || !jr_read_color(&ld->r, o, "sigma_a", false, &coefficient, &sigma_a) ||
        !jr_read_color(&ld->r, o, "sigma_s", false, &coefficient, &m.sigma_s) ||
        !jr_read_float(&ld->r, o, "g", false, &asymmetry, &m.g))
        return false;
    m.sigma_t = v3_add(sigma_a, m.sigma_s);
    if (!(v3_max_comp(m.sigma_t) > 0.0f))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, o->self.tok),
                          "%s has no effect: \"sigma_a\" + \"sigma_s\" must be > 0 in some channel", o->what);
    return add_medium(ld, m);
}
