// scene.c — building, overriding and freeing a scene (plain data: nothing here is built for rendering).
#include "scene/scene.h"
#include "core/array.h"
#include "core/names.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char *dup_string(const char *s) {
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

const char *const integrator_kind_names[INTEGRATOR_KIND_COUNT] = {"whitted", "path"};
const char *const whitted_mode_names[WHITTED_MODE_COUNT] = {"paper", "color"};
const char *const sampler_kind_names[SAMPLER_KIND_COUNT] = {"sobol", "independent"};

glint_scene *scene_new(const char *path) {
    glint_scene *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->path = dup_string(path ? path : "<scene>");
    if (!s->path) { free(s); return NULL; }
    render_settings *rs = &s->settings;
    rs->width = 400;
    rs->height = 225;
    rs->spp = 1;
    rs->max_depth = 3;
    rs->seed = 0;
    rs->integrator = INTEGRATOR_WHITTED;
    rs->whitted_mode = WHITTED_COLOR;
    rs->background = BACKGROUND_CONSTANT;
    rs->background_color = v3s(0.0f);
    rs->sky_horizon = v3(1.0f, 1.0f, 1.0f);
    rs->sky_zenith = v3(0.5f, 0.7f, 1.0f);
    rs->transform = TRANSFORM_LINEAR;
    rs->accel = ACCEL_BVH;
    rs->sampler = SAMPLER_SOBOL; // the path tracer's default; the Whitted integrators draw PCG32 whatever it says
    s->camera = camera_default();
    return s;
}

// Makes room for one more element in an array of the scene (core/array.h: one growth policy everywhere).
#define SCENE_RESERVE(s, field, count) \
    array_reserve((void **)&(s)->field, &(s)->capacity.field, (count) + 1, sizeof *(s)->field)

long scene_add_material(glint_scene *s, const material *m, const char *name) {
    if (!SCENE_RESERVE(s, materials, s->material_count) || !SCENE_RESERVE(s, material_names, s->material_count))
        return -1;
    char *copy = NULL;
    if (name && !(copy = dup_string(name))) return -1;
    s->materials[s->material_count] = *m;
    s->material_names[s->material_count] = copy;
    return (long)s->material_count++;
}

long scene_find_material(const glint_scene *s, const char *name) {
    for (size_t i = 0; i < s->material_count; i++)
        if (s->material_names[i] && strcmp(s->material_names[i], name) == 0) return (long)i;
    return -1;
}

bool scene_add_sphere(glint_scene *s, sphere sp) {
    if (!SCENE_RESERVE(s, spheres, s->sphere_count)) return false;
    s->spheres[s->sphere_count++] = sp;
    return true;
}

bool scene_add_light(glint_scene *s, light l) {
    if (!SCENE_RESERVE(s, lights, s->light_count)) return false;
    s->lights[s->light_count++] = l;
    return true;
}

bool scene_add_medium(glint_scene *s, medium m) {
    if (!SCENE_RESERVE(s, media, s->medium_count)) return false;
    s->media[s->medium_count++] = m;
    return true;
}

bool scene_add_quad(glint_scene *s, quad q) {
    if (!SCENE_RESERVE(s, quads, s->quad_count)) return false;
    s->quads[s->quad_count++] = q;
    return true;
}

long scene_add_texture(glint_scene *s, texture *t, const char *name) {
    bool room = SCENE_RESERVE(s, textures, s->texture_count) && SCENE_RESERVE(s, texture_names, s->texture_count);
    char *copy = NULL;
    if (!room || (name && !(copy = dup_string(name)))) {
        texture_free(t);
        return -1;
    }
    s->textures[s->texture_count] = *t;
    s->texture_names[s->texture_count] = copy;
    return (long)s->texture_count++;
}

long scene_find_texture(const glint_scene *s, const char *name) {
    for (size_t i = 0; i < s->texture_count; i++)
        if (s->texture_names[i] && strcmp(s->texture_names[i], name) == 0) return (long)i;
    return -1;
}

// Frees what a scene mesh owns.
static void scene_mesh_free(scene_mesh *m) {
    mesh_free(&m->geometry);
    free(m->slot_material);
    free(m->path);
}

long scene_add_mesh(glint_scene *s, scene_mesh *m) {
    if (!SCENE_RESERVE(s, meshes, s->mesh_count)) {
        scene_mesh_free(m);
        return -1;
    }
    s->meshes[s->mesh_count] = *m;
    return (long)s->mesh_count++;
}

long scene_add_instance_sphere(glint_scene *s, sphere sp) {
    if (!SCENE_RESERVE(s, instance_spheres, s->instance_sphere_count)) return -1;
    s->instance_spheres[s->instance_sphere_count] = sp;
    return (long)s->instance_sphere_count++;
}

bool scene_add_instance(glint_scene *s, instance in) {
    if (!SCENE_RESERVE(s, instances, s->instance_count)) return false;
    instance_cache(&in);
    s->instances[s->instance_count++] = in;
    return true;
}

bool scene_add_moving_sphere(glint_scene *s, moving_sphere sp) {
    if (!SCENE_RESERVE(s, moving_spheres, s->moving_sphere_count)) return false;
    s->moving_spheres[s->moving_sphere_count++] = sp;
    return true;
}

bool scene_add_importance_sphere(glint_scene *s, uint32_t index) {
    if (!SCENE_RESERVE(s, importance_spheres, s->importance_sphere_count)) return false;
    s->importance_spheres[s->importance_sphere_count++] = index;
    return true;
}

uint32_t scene_add_motion(glint_scene *s, const motion *m) {
    if (s->motion_count >= UINT32_MAX - 1 || !SCENE_RESERVE(s, motions, s->motion_count)) return 0;
    s->motions[s->motion_count++] = *m;
    return (uint32_t)s->motion_count;
}

bool scene_add_input(glint_scene *s, uint64_t dev, uint64_t ino, const char *path) {
    for (size_t i = 0; i < s->input_count; i++)
        if (s->inputs[i].dev == dev && s->inputs[i].ino == ino) return true;
    if (!SCENE_RESERVE(s, inputs, s->input_count)) return false;
    char *copy = dup_string(path);
    if (!copy) return false;
    s->inputs[s->input_count++] = (scene_input){dev, ino, copy};
    return true;
}

bool scene_reads_file(const glint_scene *s, const char *path) {
    struct stat st;
    if (!path || stat(path, &st) != 0) return false;
    for (size_t i = 0; i < s->input_count; i++)
        if (s->inputs[i].dev == (uint64_t)st.st_dev && s->inputs[i].ino == (uint64_t)st.st_ino) return true;
    return false;
}

bool scene_add_warning(glint_scene *s, const char *message) {
    if (!SCENE_RESERVE(s, warnings, s->warning_count)) return false;
    char *copy = dup_string(message);
    if (!copy) return false;
    s->warnings[s->warning_count++] = copy;
    return true;
}

// Checks one integer override against [lo, hi]; writes a message naming the flag otherwise.
static bool override_in_range(const char *flag, long v, long lo, long hi, glint_error *err) {
    if (v >= lo && v <= hi) return true;
    snprintf(err->message, sizeof err->message, "%s: %ld is out of range, expected an integer in [%ld, %ld]", flag,
             v, lo, hi);
    return false;
}

// Brute force on meshes tests every triangle of every placed mesh for every ray: a render that a BVH does in
// seconds can take hours, so the user hears it before waiting (once, however often overrides are applied).
static glint_status warn_brute_force(glint_scene *s, bool from_flag, glint_error *err) {
    uint64_t triangles = 0;
    for (size_t i = 0; i < s->instance_count; i++)
        if (s->instances[i].kind == INSTANCE_MESH) triangles += s->meshes[s->instances[i].index].geometry.triangle_count;
    if (s->settings.accel != ACCEL_NONE || triangles == 0) return GLINT_OK;
    char msg[256];
    snprintf(msg, sizeof msg,
             "warning: %s: brute force tests every one of the %llu triangle%s of the scene's meshes for every ray; "
             "the render may take far longer than with the default, bvh",
             from_flag ? "--accel none" : "\"accel\": \"none\"", (unsigned long long)triangles,
             triangles == 1 ? "" : "s");
    if (s->warning_count > 0 && strcmp(s->warnings[s->warning_count - 1], msg) == 0) return GLINT_OK;
    if (scene_add_warning(s, msg)) return GLINT_OK;
    snprintf(err->message, sizeof err->message, "out of memory");
    return GLINT_ERR_RENDER;
}

glint_status scene_override(glint_scene *s, const scene_overrides *o, glint_error *err) {
    render_settings *rs = &s->settings;
    if (o->width >= 0 && !override_in_range("--width", o->width, 1, SCENE_MAX_DIMENSION, err)) return GLINT_ERR_INPUT;
    if (o->height >= 0 && !override_in_range("--height", o->height, 1, SCENE_MAX_DIMENSION, err))
        return GLINT_ERR_INPUT;
    if (o->spp >= 0 && !override_in_range("--spp", o->spp, 1, SCENE_MAX_SPP, err)) return GLINT_ERR_INPUT;
    if (o->max_depth >= 0 && !override_in_range("--depth", o->max_depth, 0, SCENE_MAX_DEPTH, err))
        return GLINT_ERR_INPUT;
    int kind = o->accel ? names_find(accel_kind_names, ACCEL_KIND_COUNT, o->accel) : (int)rs->accel;
    if (kind < 0) {
        snprintf(err->message, sizeof err->message, "--accel: unknown structure '%s', expected bvh, bvh2 or none",
                 o->accel);
        return GLINT_ERR_INPUT;
    }
    int encoding = o->output_encoding ? names_find(output_transform_names, TRANSFORM_COUNT, o->output_encoding)
                                      : (int)rs->transform;
    if (encoding < 0) {
        snprintf(err->message, sizeof err->message,
                 "--output-encoding: unknown encoding '%s', expected linear, gamma2 or srgb", o->output_encoding);
        return GLINT_ERR_INPUT;
    }
    int sampler = o->sampler ? names_find(sampler_kind_names, SAMPLER_KIND_COUNT, o->sampler) : (int)rs->sampler;
    if (sampler < 0) {
        snprintf(err->message, sizeof err->message, "--sampler: unknown sampler '%s', expected sobol or independent",
                 o->sampler);
        return GLINT_ERR_INPUT;
    }
    if (o->noise_threshold >= 0 && !(o->noise_threshold <= SCENE_MAX_NOISE_THRESHOLD)) {
        snprintf(err->message, sizeof err->message, "--noise-threshold: %g is out of range, expected a number in "
                 "[0, %d]", o->noise_threshold, SCENE_MAX_NOISE_THRESHOLD);
        return GLINT_ERR_INPUT;
    }
    rs->transform = (output_transform)encoding;
    rs->sampler = (sampler_kind)sampler;
    if (o->noise_threshold >= 0) rs->noise_threshold = (float)o->noise_threshold;
    if (o->width >= 0) rs->width = (int)o->width;
    if (o->height >= 0) rs->height = (int)o->height;
    if (o->spp >= 0) rs->spp = (int)o->spp;
    if (o->max_depth >= 0) rs->max_depth = (int)o->max_depth;
    if (o->seed >= 0) rs->seed = (uint64_t)o->seed;
    rs->accel = (accel_kind)kind;
    return warn_brute_force(s, o->accel != NULL, err);
}

geometry_arrays scene_geometry(const glint_scene *s, const mesh **meshes) {
    for (size_t i = 0; i < s->mesh_count; i++) meshes[i] = &s->meshes[i].geometry;
    return (geometry_arrays){.spheres = s->spheres,
                             .sphere_count = s->sphere_count,
                             .quads = s->quads,
                             .quad_count = s->quad_count,
                             .meshes = meshes,
                             .mesh_count = s->mesh_count,
                             .instance_spheres = s->instance_spheres,
                             .instances = s->instances,
                             .instance_count = s->instance_count,
                             .moving_spheres = s->moving_spheres,
                             .moving_sphere_count = s->moving_sphere_count,
                             .motions = s->motions,
                             .time0 = s->camera.shutter_open,
                             .time1 = s->camera.shutter_close};
}

scene_mark scene_mark_now(const glint_scene *s) {
    return (scene_mark){s->material_count,        s->sphere_count,         s->light_count,     s->quad_count,
                        s->texture_count,         s->mesh_count,           s->instance_sphere_count,
                        s->instance_count,        s->moving_sphere_count,  s->motion_count,
                        s->importance_sphere_count, s->medium_count,       s->input_count,     s->warning_count};
}

void scene_rollback(glint_scene *s, const scene_mark *mark) {
    for (size_t i = mark->materials; i < s->material_count; i++) free(s->material_names[i]);
    for (size_t i = mark->textures; i < s->texture_count; i++) {
        texture_free(&s->textures[i]);
        free(s->texture_names[i]);
    }
    for (size_t i = mark->meshes; i < s->mesh_count; i++) scene_mesh_free(&s->meshes[i]);
    for (size_t i = mark->inputs; i < s->input_count; i++) free(s->inputs[i].path);
    for (size_t i = mark->warnings; i < s->warning_count; i++) free(s->warnings[i]);
    s->material_count = mark->materials;
    s->sphere_count = mark->spheres;
    s->light_count = mark->lights;
    s->quad_count = mark->quads;
    s->texture_count = mark->textures;
    s->mesh_count = mark->meshes;
    s->instance_sphere_count = mark->instance_spheres;
    s->instance_count = mark->instances;
    s->moving_sphere_count = mark->moving_spheres;
    s->motion_count = mark->motions;
    s->importance_sphere_count = mark->importance_spheres;
    s->medium_count = mark->media;
    s->input_count = mark->inputs;
    s->warning_count = mark->warnings;
}

void scene_free(glint_scene *s) {
    if (!s) return;
    if (s->session) s->session_free(s->session);
    for (size_t i = 0; i < s->material_count; i++) free(s->material_names[i]);
    free(s->material_names);
    free(s->materials);
    free(s->spheres);
    free(s->lights);
    free(s->quads);
    free(s->media);
    for (size_t i = 0; i < s->texture_count; i++) {
        texture_free(&s->textures[i]);
        free(s->texture_names[i]);
    }
    free(s->textures);
    free(s->texture_names);
    for (size_t i = 0; i < s->mesh_count; i++) scene_mesh_free(&s->meshes[i]);
    free(s->meshes);
    free(s->instance_spheres);
    free(s->instances);
    free(s->moving_spheres);
    free(s->importance_spheres);
    free(s->motions);
    envmap_free(&s->environment);
    for (size_t i = 0; i < s->input_count; i++) free(s->inputs[i].path);
    free(s->inputs);
    for (size_t i = 0; i < s->warning_count; i++) free(s->warnings[i]);
    free(s->warnings);
    free(s->path);
    free(s);
}
