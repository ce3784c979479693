// scene_file_objects.c — the scene file's "objects" (spheres, quads, boxes; meshes in scene_file_mesh.c, media
// in scene_file_media.c), their "transform" operations, and its "lights".
#include "scene/scene_file_common.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

// ---------------------------------------------------------------------------------------------
// Transforms: an array of operations, the first applied first (Mitsuba's order; pbrt's is the reverse)

static const char *const transform_op_keys[] = {"translate", "rotate", "scale", "matrix", NULL};
static const char *const rotate_keys[] = {"axis", "degrees", NULL};

// {"rotate": {"axis": [x, y, z], "degrees": a}}: right-handed, counter-clockwise looking down the axis.
static bool read_rotate(sf_loader *ld, jr_val v, const char *what, mat4 *out) {
    jr_obj o;
    vec3 axis;
    float degrees;
    if (!jr_open(&ld->r, v, what, rotate_keys, &o) || !jr_read_vec3(&ld->r, &o, "axis", true, &JR_FINITE, &axis) ||
        !jr_read_float(&ld->r, &o, "degrees", true, &JR_FINITE, &degrees))
        return false;
    if (axis.x == 0.0f && axis.y == 0.0f && axis.z == 0.0f) {
        const jr_member *m = jr_get(&o, "axis");
        char got[96];
        return jr_fail_at(&ld->r, jr_offset(&ld->r, m->val.tok), "\"axis\" must be a non-zero vector, got %s",
                          jr_describe(&ld->r, m->val, got, sizeof got));
    }
    *out = mat4_rotate(axis, degrees);
    return true;
}

// {"scale": s} or {"scale": [x, y, z]}: every factor non-zero (a zero would flatten the object).
static bool read_scale(sf_loader *ld, jr_val v, mat4 *out) {
    double d[3];
    if (cJSON_IsNumber(v.item)) {
        if (!jr_check_number(&ld->r, v, "scale", -1, &JR_NONZERO_FINITE, &d[0])) return false;
        d[1] = d[2] = d[0];
    } else if (cJSON_IsArray(v.item) && cJSON_GetArraySize(v.item) == 3) {
        if (!jr_check_numbers(&ld->r, v, "scale", 3, "3 numbers", &JR_NONZERO_FINITE, d)) return false;
    } else {
        char got[96];
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"scale\" must be a finite non-zero number or an array of 3 such numbers [x, y, z], got %s",
                          jr_describe(&ld->r, v, got, sizeof got));
    }
    *out = mat4_scale(v3((float)d[0], (float)d[1], (float)d[2]));
    return true;
}

// {"matrix": [16 numbers, row by row]}: affine (last row 0 0 0 1) and invertible.
static bool read_matrix(sf_loader *ld, jr_val v, mat4 *out) {
    double d[16];
    if (!jr_check_numbers(&ld->r, v, "matrix", 16, "16 numbers (a 4x4 matrix, row by row)", &JR_FINITE, d)) return false;
    for (int i = 0; i < 16; i++) out->m[i / 4][i % 4] = (float)d[i];
    if (!(d[12] == 0.0 && d[13] == 0.0 && d[14] == 0.0 && d[15] == 1.0))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"matrix\" must be affine: its last row must be [0, 0, 0, 1], got [%g, %g, %g, %g]", d[12],
                          d[13], d[14], d[15]);
    mat4 inv;
    if (!mat4_invert(out, &inv))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"matrix\" is singular (determinant %g); expected an invertible matrix", mat4_linear_det(out));
    return true;
}

// Reads the optional transform `key` of o into *xf (object to world); *given is false without one.
static bool read_transform_key(sf_loader *ld, const jr_obj *o, const char *key, transform *xf, bool *given) {
    const jr_member *m = jr_get(o, key);
    *xf = transform_identity();
    *given = m != NULL;
    if (!m) return true;
    jr_val v = m->val;
    char got[96];
    if (!cJSON_IsArray(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" must be an array of operations ({\"translate\": ...}, {\"rotate\": ...}, "
                          "{\"scale\": ...} or {\"matrix\": ...}), got %s",
                          key, jr_describe(&ld->r, v, got, sizeof got));
    mat4 acc = mat4_identity();
    jr_iter it = jr_iter_begin(&ld->r, v);
    jr_val e;
    int r;
    for (size_t i = 0; (r = jr_iter_next(&ld->r, &it, NULL, &e)) > 0; i++) {
        char what[48];
        snprintf(what, sizeof what, "%s[%zu]", key, i);
        jr_obj op;
        if (!jr_open(&ld->r, e, what, transform_op_keys, &op)) return false;
        if (op.count != 1)
            return jr_fail_at(&ld->r, jr_offset(&ld->r, e.tok),
                              "%s must hold exactly one operation (translate, rotate, scale or matrix), got %zu; put "
                              "each in its own element, they apply in array order",
                              what, op.count);
        const jr_member *opm = &op.m[0];
        mat4 step;
        if (strcmp(opm->key, "translate") == 0) {
            vec3 t;
            if (!jr_check_vec3(&ld->r, opm->val, "translate", &JR_FINITE, &t)) return false;
            step = mat4_translate(t);
        } else if (strcmp(opm->key, "rotate") == 0) {
            char rot_what[96];
            snprintf(rot_what, sizeof rot_what, "\"rotate\" of %s", what);
            if (!read_rotate(ld, opm->val, rot_what, &step)) return false;
        } else if (strcmp(opm->key, "scale") == 0) {
            if (!read_scale(ld, opm->val, &step)) return false;
        } else if (!read_matrix(ld, opm->val, &step)) {
            return false;
        }
        // Each operation acts on the result of the ones before it: M = step * M.
        acc = mat4_mul(&step, &acc);
        if (!mat4_is_affine(&acc))
            return jr_fail_at(&ld->r, jr_offset(&ld->r, e.tok), "%s makes the transform overflow single precision", what);
    }
    if (r < 0) return false;
    if (!transform_make(&acc, xf))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" is singular or too close to it to invert in single precision (determinant "
                          "%g)",
                          key, mat4_linear_det(&acc));
    return true;
}

bool sf_read_transform(sf_loader *ld, const jr_obj *o, transform *xf, bool *given) {
    return read_transform_key(ld, o, "transform", xf, given);
}

bool sf_read_motion(sf_loader *ld, const jr_obj *o, const transform *xf, bounds3 object_bounds, const char *shape,
                    uint32_t *motion_ref) {
    transform end;
    bool given;
    *motion_ref = 0;
    if (!read_transform_key(ld, o, "transform2", &end, &given)) return false;
    if (!given) return true;
    size_t where = jr_member_offset(&ld->r, o, "transform2");
    motion mo;
    if (!motion_make(&xf->m, &end.m, &mo)) {
        // Both are affine and invertible (read_transform_key checked): they differ in handedness.
        double d0 = mat4_linear_det(&xf->m), d1 = mat4_linear_det(&end.m);
        return jr_fail_at(&ld->r, where,
                          "\"transform2\" %s (determinant %g) where \"transform\" %s (determinant %g); expected two "
                          "transforms that both mirror or neither, so that the motion between them never flattens "
                          "the object",
                          d1 < 0.0 ? "mirrors" : "does not mirror", d1, d0 < 0.0 ? "does" : "does not", d0);
    }
    // The motion is defined for times in [0, 1], where every shutter lies.
    char what[96];
    snprintf(what, sizeof what, "the moving %s", shape);
    if (!bounds3_is_empty(object_bounds) &&
        !sf_check_extent(ld, where, what, motion_bounds(&mo, object_bounds, 0.0f, 1.0f)))
        return false;
    *motion_ref = scene_add_motion(ld->scene, &mo);
    return *motion_ref != 0 || sf_fail_oom(ld);
}

// ---------------------------------------------------------------------------------------------
// Objects: add a row to object_types (name, keys, reader) for a new shape.

static const char *const sphere_keys[] = {"type",      "center",     "center2",    "radius",
                                          "material",  "transform",  "transform2", "importance", NULL};
static const char *const quad_keys[] = {"type", "q", "u", "v", "material", "transform", "transform2", NULL};
static const char *const box_keys[] = {"type", "min", "max", "material", "transform", "transform2", NULL};
static const char *const mesh_keys[] = {"type", "file", "mesh", "material", "transform", "transform2", "face_normals", NULL};
static const char *const constant_medium_keys[] = {"type", "boundary", "density", "albedo", "g", NULL};
static const char *const homogeneous_medium_keys[] = {"type", "boundary", "sigma_a", "sigma_s", "g", NULL};
static const char *const import_keys[] = {"type", "file", "transform", NULL};

// Quads and boxes are baked into world-space quads: they cannot move (yet). Said where "transform2" is.
static bool refuse_motion(sf_loader *ld, const jr_obj *o, const char *shape) {
    if (!jr_get(o, "transform2")) return true;
    return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "transform2"),
                      "a %s cannot move: \"transform2\" is read for spheres and meshes only (a moving box can be a "
                      "mesh)",
                      shape);
}

// A sphere with "center2" moves along the line from "center" (time 0) to "center2" (time 1), in world space.
static bool read_moving_sphere(sf_loader *ld, const jr_obj *o, const sphere *s, vec3 center2) {
    size_t where = jr_member_offset(&ld->r, o, "center2");
    if (jr_get(o, "transform") || jr_get(o, "transform2"))
        return jr_fail_at(&ld->r, where,
                          "\"center2\" cannot be combined with \"transform\" or \"transform2\": give both centres in "
                          "world space, or move the sphere by \"transform2\" alone");
    moving_sphere ms = {s->center, v3_sub(center2, s->center), s->radius, s->material};
    float r = fabsf(s->radius);
    bounds3 b = {v3_sub(v3_min(s->center, center2), v3s(r)), v3_add(v3_max(s->center, center2), v3s(r))};
    if (!v3_is_finite(ms.motion))
        return jr_fail_at(&ld->r, where, "\"center2\" is too far from \"center\": their difference overflows single precision");
    if (!sf_check_extent(ld, where, "the moving sphere", b)) return false;
    return scene_add_moving_sphere(ld->scene, ms) || sf_fail_oom(ld);
}

// A sphere under a similarity is another sphere; under any other transform, or when its material is
// textured (the texture must turn with it), it becomes an instance.
static bool read_sphere_shape(sf_loader *ld, const jr_obj *o, const char *what);

// A sphere, which "importance": true marks as a target of diffuse bounces (it must stay a world sphere).
static bool read_sphere(sf_loader *ld, const jr_obj *o, const char *what) {
    bool importance = false;
    if (!jr_read_bool(&ld->r, o, "importance", &importance)) return false;
    size_t before = ld->scene->sphere_count;
    if (!read_sphere_shape(ld, o, what)) return false;
    if (!importance) return true;
    if (ld->scene->sphere_count == before)
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "importance"),
                          "\"importance\" needs a sphere that stays a sphere in world space: not moving, and without "
                          "a non-uniform transform (nor a transform with a textured material)");
    return scene_add_importance_sphere(ld->scene, (uint32_t)before) || sf_fail_oom(ld);
}

static bool read_sphere_shape(sf_loader *ld, const jr_obj *o, const char *what) {
    sphere s = {0};
    transform xf;
    bool moved;
    if (!jr_read_vec3(&ld->r, o, "center", true, &JR_FINITE, &s.center) ||
        !jr_read_float(&ld->r, o, "radius", true, &JR_NONZERO_FINITE, &s.radius) ||
        !sf_read_material_ref(ld, o, what, &s.material) || !sf_read_transform(ld, o, &xf, &moved))
        return false;
    if (jr_get(o, "center2")) {
        vec3 center2;
        if (!jr_read_vec3(&ld->r, o, "center2", true, &JR_FINITE, &center2)) return false;
        // The same centre at both times: a sphere that does not move (book 2 writes its static spheres so).
        if (center2.x != s.center.x || center2.y != s.center.y || center2.z != s.center.z || jr_get(o, "transform") ||
            jr_get(o, "transform2"))
            return read_moving_sphere(ld, o, &s, center2);
    }
    float rad = fabsf(s.radius);
    bounds3 object_box = {v3_sub(s.center, v3s(rad)), v3_add(s.center, v3s(rad))};
    uint32_t motion_ref;
    if (!sf_read_motion(ld, o, &xf, object_box, "sphere", &motion_ref)) return false;
    if (motion_ref) { // always an instance: its transform changes with time
        long i = scene_add_instance_sphere(ld->scene, s);
        if (i < 0) return sf_fail_oom(ld);
        instance in = {.kind = INSTANCE_SPHERE, .index = (uint32_t)i, .xf = xf, .material = (int32_t)s.material,
                       .motion = motion_ref};
        return scene_add_instance(ld->scene, in) || sf_fail_oom(ld);
    }
    size_t where = jr_member_offset(&ld->r, o, moved ? "transform" : "center");
    if (!moved) {
        float r = fabsf(s.radius);
        bounds3 b = {v3_sub(s.center, v3s(r)), v3_add(s.center, v3s(r))};
        if (!sf_check_extent(ld, where, "the sphere", b)) return false;
        return scene_add_sphere(ld->scene, s) || sf_fail_oom(ld);
    }
    double scale;
    const material *m = &ld->scene->materials[s.material];
    bool textured = m->albedo_texture >= 0 || m->emission_texture >= 0 || m->alpha_texture >= 0;
    if (!textured && mat4_similarity_scale(&xf.m, &scale)) {
        sphere w = s;
        w.center = mat4_apply_point(&xf.m, s.center);
        w.radius = (float)(s.radius * scale);
        if (!v3_is_finite(w.center) || !isfinite(w.radius) || w.radius == 0.0f)
            return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "transform"),
                              "the transformed sphere is not representable in single precision");
        float r = fabsf(w.radius);
        bounds3 b = {v3_sub(w.center, v3s(r)), v3_add(w.center, v3s(r))};
        if (!sf_check_extent(ld, where, "the transformed sphere", b)) return false;
        return scene_add_sphere(ld->scene, w) || sf_fail_oom(ld);
    }
    float r = fabsf(s.radius);
    bounds3 ob = {v3_sub(s.center, v3s(r)), v3_add(s.center, v3s(r))};
    if (!sf_check_extent(ld, where, "the transformed sphere", mat4_apply_bounds(&xf.m, ob))) return false;
    long i = scene_add_instance_sphere(ld->scene, s);
    if (i < 0) return sf_fail_oom(ld);
    instance in = {.kind = INSTANCE_SPHERE, .index = (uint32_t)i, .xf = xf, .material = (int32_t)s.material};
    return scene_add_instance(ld->scene, in) || sf_fail_oom(ld);
}

// Adds quads (count of them) under xf if `moved`, pointing at "transform" when the result degenerates.
static bool add_quads(sf_loader *ld, const jr_obj *o, const quad *q, int count, const transform *xf, bool moved) {
    for (int i = 0; i < count; i++) {
        quad w = q[i];
        if (moved && !quad_transform(&q[i], &xf->m, &w))
            return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "transform"),
                              "the transformed shape has no area or is not representable in single precision");
        if (!sf_check_extent(ld, jr_member_offset(&ld->r, o, moved ? "transform" : count == 1 ? "q" : "max"),
                             moved ? "the transformed shape" : "the shape", quad_bounds(&w)))
            return false;
        if (!scene_add_quad(ld->scene, w)) return sf_fail_oom(ld);
    }
    return true;
}

static bool read_quad(sf_loader *ld, const jr_obj *o, const char *what) {
    vec3 q, u, v;
    uint32_t mat;
    transform xf;
    bool moved;
    if (!jr_read_vec3(&ld->r, o, "q", true, &JR_FINITE, &q) || !jr_read_vec3(&ld->r, o, "u", true, &JR_FINITE, &u) ||
        !jr_read_vec3(&ld->r, o, "v", true, &JR_FINITE, &v) || !sf_read_material_ref(ld, o, what, &mat) ||
        !sf_read_transform(ld, o, &xf, &moved) || !refuse_motion(ld, o, "quad"))
        return false;
    quad qd;
    if (!quad_make(q, u, v, mat, &qd)) {
        vec3 n = v3_cross(u, v);
        if (v3_is_finite(n) && n.x == 0.0f && n.y == 0.0f && n.z == 0.0f)
            return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "v"),
                              "\"u\" and \"v\" must be non-zero and not parallel (the quad has no area)");
        if (!v3_is_finite(n))
            return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "v"), "the quad is too large: its area overflows single precision");
        // The area fits, but its square (the squared length of u x v, which normalising the normal takes) does not.
        double area = sqrt((double)n.x * n.x + (double)n.y * n.y + (double)n.z * n.z);
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "v"),
                          "the quad is too large: its area %g exceeds %.3g, the largest whose square fits in single "
                          "precision", area, sqrt((double)FLT_MAX));
    }
    return add_quads(ld, o, &qd, 1, &xf, moved);
}

static bool read_box(sf_loader *ld, const jr_obj *o, const char *what) {
    vec3 lo, hi;
    uint32_t mat;
    transform xf;
    bool moved;
    if (!jr_read_vec3(&ld->r, o, "min", true, &JR_FINITE, &lo) || !jr_read_vec3(&ld->r, o, "max", true, &JR_FINITE, &hi))
        return false;
    for (int k = 0; k < 3; k++) {
        float a = v3_comp(lo, k), b = v3_comp(hi, k);
        if (!(a < b))
            return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "max"),
                              "\"max\" must be greater than \"min\" in every coordinate, but \"max\"[%d] = %g <= "
                              "\"min\"[%d] = %g",
                              k, (double)b, k, (double)a);
    }
    if (!sf_read_material_ref(ld, o, what, &mat) || !sf_read_transform(ld, o, &xf, &moved) || !refuse_motion(ld, o, "box"))
        return false;
    quad faces[6];
    if (!quad_box(lo, hi, mat, faces))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "max"), "the box is too large: its faces' areas overflow single "
                                                           "precision");
    return add_quads(ld, o, faces, 6, &xf, moved);
}

typedef bool (*object_reader)(sf_loader *ld, const jr_obj *o, const char *what);

static const struct object_type {
    const char *name;
    const char *const *keys;
    object_reader read;
} object_types[] = { // in the order of sf_object_kind
    {"sphere", sphere_keys, read_sphere},
    {"quad", quad_keys, read_quad},
    {"box", box_keys, read_box},
    {"mesh", mesh_keys, sf_read_mesh},
    {"constant_medium", constant_medium_keys, sf_read_constant_medium},
    {"homogeneous_medium", homogeneous_medium_keys, sf_read_homogeneous_medium},
    {"import", import_keys, sf_read_import},
};
#define OBJECT_TYPES (sizeof object_types / sizeof object_types[0])

bool sf_read_object(sf_loader *ld, jr_val v, size_t i) {
    char what[64], typed[96];
    size_t t;
    snprintf(what, sizeof what, "object %zu", i);
    if (!jr_open_typed(&ld->r, v, what, object_types, OBJECT_TYPES, sizeof object_types[0], &t)) return false;
    snprintf(typed, sizeof typed, "object %zu (%s)", i, object_types[t].name);
    jr_obj o;
    if (!jr_open(&ld->r, v, typed, object_types[t].keys, &o) || !object_types[t].read(ld, &o, typed)) return false;
    ld->object_counts[t]++;
    return true;
}

// ---------------------------------------------------------------------------------------------
// Lights

static const char *const ambient_keys[] = {"type", "intensity", NULL};
static const char *const point_keys[] = {"type", "intensity", "position", NULL};
static const char *const directional_keys[] = {"type", "intensity", "direction", NULL};
static const char *const spot_keys[] = {"type", "intensity", "position", "direction", "inner_angle", "outer_angle", NULL};

static const struct light_type {
    light_kind kind;
    const char *const *keys;
} light_types[] = {
    {LIGHT_AMBIENT, ambient_keys},
    {LIGHT_POINT, point_keys},
    {LIGHT_DIRECTIONAL, directional_keys},
    {LIGHT_SPOT, spot_keys},
};
#define LIGHT_TYPES (sizeof light_types / sizeof light_types[0])

static const jr_numspec NUM_CONE = {0.0, 90.0, JR_FLOAT, "an angle in [0, 90] degrees"};

// A spot light: a point light at "position" shining along "direction", full inside "inner_angle" (degrees from
// the axis, default 0), nothing beyond "outer_angle" (default 45), falling off between (light_spot_falloff).
static bool read_spot(sf_loader *ld, const jr_obj *o, light *l) {
    float inner = 0.0f, outer = 45.0f;
    if (!jr_read_vec3(&ld->r, o, "position", true, &JR_FINITE, &l->position) ||
        !sf_check_extent(ld, jr_member_offset(&ld->r, o, "position"), "the light", (bounds3){l->position, l->position}) ||
        !jr_read_vec3(&ld->r, o, "direction", true, &JR_FINITE, &l->direction) ||
        !jr_read_float(&ld->r, o, "inner_angle", false, &NUM_CONE, &inner) ||
        !jr_read_float(&ld->r, o, "outer_angle", false, &NUM_CONE, &outer))
        return false;
    float len = v3_len(l->direction);
    if (!(len > 0.0f) || !isfinite(len))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "direction"), "\"direction\" must be a non-zero vector");
    if (!(inner < outer))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, jr_get(o, "inner_angle") ? "inner_angle" : "outer_angle"),
                          "\"inner_angle\" (%g) must be less than \"outer_angle\" (%g)", (double)inner, (double)outer);
    const float deg = 3.14159265358979f / 180.0f;
    l->direction = v3_scale(l->direction, 1.0f / len);
    l->cos_inner = cosf(inner * deg);
    l->cos_outer = cosf(outer * deg);
    return scene_add_light(ld->scene, *l) || sf_fail_oom(ld);
}

bool sf_read_light(sf_loader *ld, jr_val v, size_t i) {
    char what[64], typed[96];
    // The light module names the kinds (light_kind_name), so the file format and the code say the same.
    const char *names[LIGHT_TYPES];
    for (size_t k = 0; k < LIGHT_TYPES; k++) names[k] = light_kind_name(light_types[k].kind);
    size_t t;
    snprintf(what, sizeof what, "light %zu", i);
    if (!jr_open_typed(&ld->r, v, what, names, LIGHT_TYPES, sizeof names[0], &t)) return false;
    snprintf(typed, sizeof typed, "light %zu (%s)", i, names[t]);
    jr_obj o;
    if (!jr_open(&ld->r, v, typed, light_types[t].keys, &o)) return false;
    light l = {0};
    l.kind = light_types[t].kind;
    if (!jr_read_color(&ld->r, &o, "intensity", true, &JR_NONNEG, &l.intensity)) return false;
    if (l.kind == LIGHT_SPOT) return read_spot(ld, &o, &l);
    if (l.kind == LIGHT_POINT && (!jr_read_vec3(&ld->r, &o, "position", true, &JR_FINITE, &l.position) ||
                                  !sf_check_extent(ld, jr_member_offset(&ld->r, &o, "position"), "the light",
                                                   (bounds3){l.position, l.position})))
        return false;
    if (l.kind == LIGHT_DIRECTIONAL) {
        if (!jr_read_vec3(&ld->r, &o, "direction", true, &JR_FINITE, &l.direction)) return false;
        if (l.direction.x == 0.0f && l.direction.y == 0.0f && l.direction.z == 0.0f) {
            const jr_member *m = jr_get(&o, "direction");
            char got[96];
            return jr_fail_at(&ld->r, jr_offset(&ld->r, m->val.tok), "\"direction\" must be a non-zero vector, got %s",
                              jr_describe(&ld->r, m->val, got, sizeof got));
        }
    }
    return scene_add_light(ld->scene, l) || sf_fail_oom(ld);
}
