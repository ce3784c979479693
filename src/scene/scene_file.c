// scene_file.c — the strict JSON scene reader's entry points (scene_file_parse, scene_file_load), the
// scene's top level and its "render" and "camera" sections; the other sections are read by the other
// scene_file_*.c files, over the helpers of scene_file_common.c. A scene file becomes a glint_scene, or one
// message "file:line:col: what is wrong, what was expected" (docs/scene-format.md documents every key).
#include "scene/scene_file_common.h"
#include "core/array.h"
#include "core/file_read.h"
#include "core/hash.h"
#include "core/trace.h"
#include "io/map_read.h"
#include "io/json_scan.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

// ---------------------------------------------------------------------------------------------
// The material and texture name tables, filled as their collections are read

bool sf_names_add(sf_names *t, const char *name, uint32_t index, uint32_t tok) {
    size_t n = strlen(name) + 1;
    char *copy = malloc(n);
    if (!copy) return false;
    memcpy(copy, name, n);
    if (!array_reserve((void **)&t->list, &t->cap, t->count + 1, sizeof *t->list) ||
        !strmap_put(&t->map, copy, n - 1, t->count)) {
        free(copy);
        return false;
    }
    t->list[t->count++] = (sf_name){copy, index, tok};
    return true;
}

void sf_names_free(sf_names *t) {
    for (size_t i = 0; i < t->count; i++) free(t->list[i].name);
    strmap_free(&t->map);
    free(t->list);
}

bool sf_check_new_name(sf_loader *ld, const sf_names *map, size_t offset, const char *name, const char *shown,
                       const char *kind) {
    size_t n = strlen(name);
    if (n == 0 || n > SCENE_MAX_NAME)
        return jr_fail_at(&ld->r, offset, "%s name %s must be 1 to %d bytes long", kind, shown, SCENE_MAX_NAME);
    for (size_t i = 0; i < n; i++)
        if ((unsigned char)name[i] < 0x20)
            return jr_fail_at(&ld->r, offset, "%s name %s must not contain control characters", kind, shown);
    const sf_name *prev = sf_names_find(map, name);
    if (!prev) return true;
    // A name defined by an earlier call of the scene API has no place in this call's text.
    if (ld->r.call || prev->tok == UINT32_MAX)
        return jr_fail_at(&ld->r, offset, "duplicate %s name \"%s\" (defined by an earlier call)", kind, name);
    size_t line, col;
    json_line_col(ld->r.text, ld->r.len, jr_offset(&ld->r, prev->tok), &line, &col);
    return jr_fail_at(&ld->r, offset, "duplicate %s name \"%s\" (first defined at %zu:%zu)", kind, name, line, col);
}

// ---------------------------------------------------------------------------------------------
// The two shapes of a top-level collection: an object mapping names to items, an array of items

/// Reads one named ("textures", "materials") or inline item into the scene; *index is its number.
typedef bool (*named_reader)(sf_loader *ld, jr_val v, const char *what, const char *name, uint32_t *index);

/// Reads "<kind>s", an object mapping names to items of that kind, adding each name to `map`.
static bool read_named(sf_loader *ld, jr_val v, const char *kind, sf_names *map, named_reader read) {
    char got[96], what[64 + SCENE_MAX_NAME];
    if (!cJSON_IsObject(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "\"%ss\" must be a JSON object mapping names to %ss, got %s", kind,
                          kind, jr_describe(&ld->r, v, got, sizeof got));
    jr_iter it = jr_iter_begin(&ld->r, v);
    uint32_t kt = 0;
    jr_val val;
    int r;
    while ((r = jr_iter_next(&ld->r, &it, &kt, &val)) > 0) {
        // The key string lives in the cJSON tree for the whole parse: the map may point at it.
        const char *name = val.item->string;
        char shown[96];
        if (!sf_check_new_name(ld, map, jr_offset(&ld->r, kt), name, jr_key_source(&ld->r, kt, shown, sizeof shown), kind))
            return false;
        snprintf(what, sizeof what, "%s \"%s\"", kind, name);
        uint32_t index;
        if (!read(ld, val, what, name, &index)) return false;
        if (!sf_names_add(map, name, index, kt)) return sf_fail_oom(ld);
    }
    return r == 0;
}

/// Reads element i of an array ("objects", "lights") into the scene.
typedef bool (*element_reader)(sf_loader *ld, jr_val v, size_t i);

/// Reads `key`, an array of at most SF_MAX_ITEMS objects.
static bool read_array(sf_loader *ld, jr_val v, const char *key, element_reader read) {
    char got[96];
    if (!cJSON_IsArray(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "\"%s\" must be an array of objects, got %s", key,
                          jr_describe(&ld->r, v, got, sizeof got));
    jr_iter it = jr_iter_begin(&ld->r, v);
    jr_val e;
    int r;
    for (size_t i = 0; (r = jr_iter_next(&ld->r, &it, NULL, &e)) > 0; i++) {
        if (i >= SF_MAX_ITEMS)
            return jr_fail_at(&ld->r, jr_offset(&ld->r, e.tok), "too many %s (the limit is %d)", key, SF_MAX_ITEMS);
        if (!read(ld, e, i)) return false;
    }
    return r == 0;
}

// ---------------------------------------------------------------------------------------------
// Camera

static const jr_numspec NUM_VFOV = {0.0, 180.0, JR_FLOAT | JR_LO_OPEN | JR_HI_OPEN, "a number in (0, 180)"};
static const jr_numspec NUM_DEFOCUS = {0.0, 180.0, JR_FLOAT | JR_HI_OPEN, "a number in [0, 180)"};

static const char *const viewport_keys[] = {"type", "position", "viewport", "distance", "shutter", NULL};
static const char *const lookat_keys[] = {"type",          "lookfrom",       "lookat",  "vup", "vfov",
                                          "defocus_angle", "focus_distance", "shutter", NULL};
static const jr_numspec NUM_TIME = {0.0, 1.0, JR_FLOAT, "a time in [0, 1]"};
static const char *const import_camera_keys[] = {"type", "file", "name", "transform", "shutter", NULL};

// "shutter": [open, close], times in [0, 1] (the span over which objects' motions are defined), open <= close.
static bool read_shutter(sf_loader *ld, const jr_obj *o, camera *c) {
    const jr_member *m = jr_get(o, "shutter");
    if (!m) return true;
    double t[2];
    if (!jr_check_numbers(&ld->r, m->val, "shutter", 2, "2 times [open, close]", &NUM_TIME, t)) return false;
    if (!(t[0] <= t[1]))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, m->val.tok),
                          "\"shutter\" closes before it opens ([%g, %g]); expected [open, close] with open <= close",
                          t[0], t[1]);
    c->shutter_open = (float)t[0];
    c->shutter_close = (float)t[1];
    return true;
}

static const struct camera_type {
    const char *name;
    camera_kind kind;
    const char *const *keys;
} camera_types[] = {
    {"viewport", CAMERA_VIEWPORT, viewport_keys},
    {"lookat", CAMERA_LOOKAT, lookat_keys},
    {"import", CAMERA_LOOKAT, import_camera_keys}, // a glTF file's camera, as a look-at camera (scene_file_import.c)
};

// The camera's film for the widest and the tallest image allowed must lie within the extent (a huge focus
// distance or a field of view near 180 degrees put it far away, and its rays' squared lengths overflow).
static bool check_camera_extent(sf_loader *ld, const jr_obj *o, const camera *c) {
    static const int sizes[2][2] = {{SCENE_MAX_DIMENSION, 1}, {1, SCENE_MAX_DIMENSION}};
    for (int i = 0; i < 2; i++) {
        camera p = *c;
        camera_prepare(&p, sizes[i][0], sizes[i][1]);
        vec3 corner = v3_add(p.pixel00, v3_add(v3_scale(p.pixel_du, (float)sizes[i][0]), v3_scale(p.pixel_dv, (float)sizes[i][1])));
        bounds3 b = bounds3_add(bounds3_add(bounds3_add(bounds3_empty(), p.pixel00), corner), p.origin);
        b = bounds3_add(bounds3_add(b, v3_add(p.origin, p.defocus_u)), v3_add(p.origin, p.defocus_v));
        const char *key = jr_get(o, "focus_distance") ? "focus_distance" : jr_get(o, "vfov") ? "vfov" : "lookfrom";
        if (c->kind == CAMERA_VIEWPORT) key = jr_get(o, "position") ? "position" : jr_get(o, "viewport") ? "viewport" : "distance";
        if (!sf_check_extent(ld, jr_member_offset(&ld->r, o, key), "the camera's view", b)) return false;
    }
    return true;
}

static bool read_lookat(sf_loader *ld, const jr_obj *o, camera *c) {
    if (!jr_read_vec3(&ld->r, o, "lookfrom", false, &JR_FINITE, &c->lookfrom) ||
        !jr_read_vec3(&ld->r, o, "lookat", false, &JR_FINITE, &c->lookat) ||
        !jr_read_vec3(&ld->r, o, "vup", false, &JR_FINITE, &c->vup) ||
        !jr_read_float(&ld->r, o, "vfov", false, &NUM_VFOV, &c->vfov_degrees) ||
        !jr_read_float(&ld->r, o, "defocus_angle", false, &NUM_DEFOCUS, &c->defocus_angle_degrees) ||
        !jr_read_float(&ld->r, o, "focus_distance", false, &JR_NONNEG, &c->focus_distance))
        return false;
    // The camera basis (camera_prepare, in float) needs a view direction and an up vector not along it.
    vec3 d = v3_sub(c->lookfrom, c->lookat);
    float d2 = v3_len2(d);
    if (!(d2 > 0.0f) || !isfinite(d2))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, jr_get(o, "lookat") ? "lookat" : "lookfrom"),
                          "\"lookfrom\" and \"lookat\" must be different points%s",
                          d2 > 0.0f ? " not so far apart that their distance overflows" : "");
    float up2 = v3_len2(c->vup);
    vec3 side = v3_cross(c->vup, v3_unit(d));
    if (!isfinite(up2) || !(v3_len2(side) > 1e-12f * up2))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "vup"),
                          "\"vup\" must be a non-zero vector not parallel to the view direction (lookat - lookfrom)");
    return true;
}

static bool read_viewport(sf_loader *ld, const jr_obj *o, camera *c) {
    const jr_member *m = jr_get(o, "position");
    if (m && !jr_check_numbers(&ld->r, m->val, "position", 3, "3 numbers (x, y, z)", &JR_FINITE_DOUBLE, c->position))
        return false;
    m = jr_get(o, "viewport");
    double size[2];
    if (m) {
        if (!jr_check_numbers(&ld->r, m->val, "viewport", 2, "2 numbers (width, height)", &JR_POSITIVE_DOUBLE, size))
            return false;
        c->viewport_width = size[0];
        c->viewport_height = size[1];
    }
    return jr_read_double(&ld->r, o, "distance", false, &JR_POSITIVE_DOUBLE, &c->distance);
}

bool sf_read_camera(sf_loader *ld, jr_val v) {
    size_t t;
    if (!jr_open_typed(&ld->r, v, "camera", camera_types, 3, sizeof camera_types[0], &t)) return false;
    char typed[64];
    snprintf(typed, sizeof typed, "camera (%s)", camera_types[t].name);
    jr_obj o;
    if (!jr_open(&ld->r, v, typed, camera_types[t].keys, &o)) return false;
    camera *c = &ld->scene->camera;
    if (t == 2) return sf_read_import_camera(ld, &o, c);
    *c = camera_default();
    c->kind = camera_types[t].kind;
    if (c->kind == CAMERA_VIEWPORT) {
        c->position[0] = c->position[1] = c->position[2] = 0.0;
        c->viewport_width = c->viewport_height = c->distance = 1.0;
        return read_viewport(ld, &o, c) && check_camera_extent(ld, &o, c) && read_shutter(ld, &o, c);
    }
    return read_lookat(ld, &o, c) && check_camera_extent(ld, &o, c) && read_shutter(ld, &o, c);
}

// ---------------------------------------------------------------------------------------------
// Render settings

static const char *const render_keys[] = {"width",      "height",   "spp",        "max_depth",
                                          "seed",       "sampler",  "noise_threshold", "integrator",
                                          "background", "output",   "accel",      "presplit",
                                          "spatial_splits", NULL};
/// Adaptive sampling's threshold (render_settings.noise_threshold; 0: off).
static const jr_numspec NUM_NOISE_THRESHOLD = {0.0, SCENE_MAX_NOISE_THRESHOLD, JR_FLOAT, "a number in [0, 1000]"};
static const char *const whitted_keys[] = {"type", "mode", NULL};
static const char *const path_keys[] = {"type", NULL};
static const char *const sky_keys[] = {"type", "horizon", "zenith", NULL};
static const char *const constant_keys[] = {"type", "color", NULL};

static const struct integrator_type {
    const char *name;
    integrator_kind kind;
    const char *const *keys;
} integrator_types[] = {
    {"whitted", INTEGRATOR_WHITTED, whitted_keys},
    {"path", INTEGRATOR_PATH, path_keys},
};

static const char *const envmap_keys[] = {"type", "file", "scale", "rotate", NULL};
static const jr_numspec NUM_ENVMAP_SCALE = {0.0, 1e30, JR_FLOAT, "a number in [0, 1e30]"};
static const jr_numspec NUM_DEGREES = {-1e6, 1e6, JR_FLOAT, "a number of degrees in [-1e6, 1e6]"};

// An environment map: an equirectangular OpenEXR or Radiance .hdr image (light/envmap.h: its orientation).
static bool read_envmap(sf_loader *ld, const jr_obj *o) {
    char *path;
    sf_file_id id;
    jr_val where;
    if (!sf_read_file_path(ld, o, "file", "environment map", &path, &id, &where)) return false;
    float scale = 1.0f, degrees = 0.0f;
    if (!jr_read_float(&ld->r, o, "scale", false, &NUM_ENVMAP_SCALE, &scale) ||
        !jr_read_float(&ld->r, o, "rotate", false, &NUM_DEGREES, &degrees)) {
        free(path);
        return false;
    }
    image_rgb img;
    glint_error err;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = map_read(path, MAP_ANY, &img, &err);
    if (lane)
        trace_add(lane, &(trace_event){"environment map read", "load", began, trace_clock(), 1, {{"file", 0, path}}});
    // The reader's message names the resolved path; the scene's message names the file as written instead.
    size_t n = strlen(path);
    const char *why = strncmp(err.message, path, n) == 0 && err.message[n] == ':' ? err.message + n + 2 : err.message;
    free(path);
    if (st != GLINT_OK) {
        bool failed = jr_fail_at(&ld->r, jr_offset(&ld->r, where.tok), "environment map \"%.300s\": %s",
                                 where.item->valuestring, why);
        ld->r.status = st; // out of memory stays a resource failure
        return failed;
    }
    envmap_free(&ld->scene->environment);
    ld->scene->environment = envmap_make(img, scale, degrees);
    return true;
}

static const struct background_type {
    const char *name;
    background_kind kind;
    const char *const *keys;
} background_types[] = {
    {"constant", BACKGROUND_CONSTANT, constant_keys},
    {"sky", BACKGROUND_SKY, sky_keys},
    {"envmap", BACKGROUND_ENVMAP, envmap_keys},
};

static bool read_integrator(sf_loader *ld, jr_val v, render_settings *rs) {
    char got[96];
    if (cJSON_IsString(v.item)) {
        size_t t = jr_find_name(integrator_types, 2, sizeof integrator_types[0], v.item->valuestring);
        if (t < 2) {
            rs->integrator = integrator_types[t].kind;
            return true;
        }
    }
    if (!cJSON_IsObject(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"integrator\" must be \"whitted\", \"path\" or an object with a \"type\", got %s",
                          jr_describe(&ld->r, v, got, sizeof got));
    size_t t;
    if (!jr_open_typed(&ld->r, v, "integrator", integrator_types, 2, sizeof integrator_types[0], &t)) return false;
    char typed[64];
    snprintf(typed, sizeof typed, "integrator (%s)", integrator_types[t].name);
    jr_obj o;
    if (!jr_open(&ld->r, v, typed, integrator_types[t].keys, &o)) return false;
    rs->integrator = integrator_types[t].kind;
    static const char *const modes[] = {"paper", "color"};
    int mode = rs->whitted_mode == WHITTED_PAPER ? 0 : 1;
    if (!jr_read_enum(&ld->r, &o, "mode", modes, 2, &mode)) return false;
    rs->whitted_mode = mode == 0 ? WHITTED_PAPER : WHITTED_COLOR;
    return true;
}

static bool read_background(sf_loader *ld, jr_val v, render_settings *rs) {
    char got[96];
    if (cJSON_IsNumber(v.item) || cJSON_IsArray(v.item)) {
        rs->background = BACKGROUND_CONSTANT;
        return jr_check_color(&ld->r, v, "background", &JR_NONNEG, &rs->background_color);
    }
    if (cJSON_IsString(v.item) && strcmp(v.item->valuestring, "sky") == 0) {
        rs->background = BACKGROUND_SKY;
        return true;
    }
    if (!cJSON_IsObject(v.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"background\" must be a colour (a number or [r, g, b]), \"sky\" or an object with a \"type\", "
                          "got %s",
                          jr_describe(&ld->r, v, got, sizeof got));
    size_t t;
    if (!jr_open_typed(&ld->r, v, "background", background_types, 3, sizeof background_types[0], &t)) return false;
    char typed[64];
    snprintf(typed, sizeof typed, "background (%s)", background_types[t].name);
    jr_obj o;
    if (!jr_open(&ld->r, v, typed, background_types[t].keys, &o)) return false;
    rs->background = background_types[t].kind;
    if (rs->background == BACKGROUND_ENVMAP) return read_envmap(ld, &o);
    if (rs->background == BACKGROUND_CONSTANT)
        return jr_read_color(&ld->r, &o, "color", true, &JR_NONNEG, &rs->background_color);
    return jr_read_color(&ld->r, &o, "horizon", false, &JR_NONNEG, &rs->sky_horizon) &&
           jr_read_color(&ld->r, &o, "zenith", false, &JR_NONNEG, &rs->sky_zenith);
}

bool sf_read_render(sf_loader *ld, jr_val v) {
    jr_obj o;
    if (!jr_open(&ld->r, v, "render", render_keys, &o)) return false;
    render_settings *rs = &ld->scene->settings;
    long long width = rs->width, height = rs->height, spp = rs->spp, depth = -1, seed = (long long)rs->seed;
    if (!jr_read_int(&ld->r, &o, "width", false, 1, SCENE_MAX_DIMENSION, &width) ||
        !jr_read_int(&ld->r, &o, "height", false, 1, SCENE_MAX_DIMENSION, &height) ||
        !jr_read_int(&ld->r, &o, "spp", false, 1, SCENE_MAX_SPP, &spp) ||
        !jr_read_int(&ld->r, &o, "max_depth", false, 0, SCENE_MAX_DEPTH, &depth) ||
        !jr_read_int(&ld->r, &o, "seed", false, 0, 9007199254740992LL, &seed))
        return false;
    const jr_member *m = jr_get(&o, "integrator");
    if (m && !read_integrator(ld, m->val, rs)) return false;
    m = jr_get(&o, "background");
    if (m && !read_background(ld, m->val, rs)) return false;
    int output = -1, structure = -1, sampler = (int)rs->sampler;
    if (!jr_read_enum(&ld->r, &o, "output", output_transform_names, TRANSFORM_COUNT, &output) ||
        !jr_read_enum(&ld->r, &o, "accel", accel_kind_names, ACCEL_KIND_COUNT, &structure) ||
        !jr_read_enum(&ld->r, &o, "sampler", sampler_kind_names, SAMPLER_KIND_COUNT, &sampler) ||
        !jr_read_float(&ld->r, &o, "noise_threshold", false, &NUM_NOISE_THRESHOLD, &rs->noise_threshold))
        return false;
    rs->sampler = (sampler_kind)sampler;
    if (output >= 0) rs->transform = (output_transform)output;
    ld->output_given = output >= 0;
    if (structure >= 0) rs->accel = (accel_kind)structure;
    bool presplit = !rs->no_presplit;
    if (!jr_read_bool(&ld->r, &o, "presplit", &presplit)) return false;
    rs->no_presplit = !presplit;
    bool spatial = !rs->no_spatial;
    if (!jr_read_bool(&ld->r, &o, "spatial_splits", &spatial)) return false;
    rs->no_spatial = !spatial;
    rs->width = (int)width;
    rs->height = (int)height;
    rs->spp = (int)spp;
    rs->seed = (uint64_t)seed;
    // Without "max_depth" each integrator gets its own default: the paper's 3 bounces, the book's 50.
    if (depth >= 0) rs->max_depth = (int)depth;
    else rs->max_depth = rs->integrator == INTEGRATOR_PATH ? 50 : 3;
    return true;
}

// ---------------------------------------------------------------------------------------------
// The scene

static const char *const scene_keys[] = {"render", "camera", "textures", "materials", "objects", "lights", NULL};

static bool read_scene(sf_loader *ld, jr_val root) {
    jr_obj o;
    if (!cJSON_IsObject(root.item)) {
        char got[96];
        return jr_fail_at(&ld->r, jr_offset(&ld->r, root.tok), "the scene must be a JSON object, got %s",
                          jr_describe(&ld->r, root, got, sizeof got));
    }
    if (!jr_open(&ld->r, root, "the scene", scene_keys, &o)) return false;
    const jr_member *m;
    // Textures before materials before objects, so that each can refer to the one before it whatever the
    // key order in the file.
    if ((m = jr_get(&o, "render")) && !sf_read_render(ld, m->val)) return false;
    if ((m = jr_get(&o, "camera")) && !sf_read_camera(ld, m->val)) return false;
    if ((m = jr_get(&o, "textures")) && !read_named(ld, m->val, "texture", &ld->textures, sf_read_texture)) return false;
    if ((m = jr_get(&o, "materials")) && !read_named(ld, m->val, "material", &ld->materials, sf_read_material))
        return false;
    if ((m = jr_get(&o, "objects")) && !read_array(ld, m->val, "objects", sf_read_object)) return false;
    if ((m = jr_get(&o, "lights")) && !read_array(ld, m->val, "lights", sf_read_light)) return false;
    return sf_finish(ld);
}

void sf_default_output(sf_loader *ld) {
    // Without "output", 8-bit images are sRGB (what displays and image viewers expect), except in paper mode,
    // whose program wrote its linear values as they are.
    render_settings *rs = &ld->scene->settings;
    if (!ld->output_given)
        rs->transform = rs->integrator == INTEGRATOR_WHITTED && rs->whitted_mode == WHITTED_PAPER ? TRANSFORM_LINEAR
                                                                                                  : TRANSFORM_SRGB;
}

bool sf_finish(sf_loader *ld) {
    sf_default_output(ld);
    sf_warn_unseen(ld);
    if (ld->warnings_dropped) {
        char msg[256];
        snprintf(msg, sizeof msg, "%s: warning: %zu more warnings not listed", ld->r.name, ld->warnings_dropped);
        ld->warnings_dropped = 0;
        if (!scene_add_warning(ld->scene, msg)) ld->warning_oom = true;
    }
    return !ld->warning_oom || sf_fail_oom(ld);
}

void sf_loader_init(sf_loader *ld, glint_scene *scene, const char *name, int threads, glint_error *err) {
    memset(ld, 0, sizeof *ld);
    ld->r = (json_reader){name, "", 0, NULL, err, GLINT_ERR_INPUT, false};
    ld->scene = scene;
    ld->base = name;
    ld->fallback_material = -1;
    ld->mesh_threads = threads;
}

void sf_loader_release(sf_loader *ld) {
    sf_names_free(&ld->materials);
    sf_names_free(&ld->textures);
    sf_names_free(&ld->api_meshes);
    free(ld->meshes);
    free(ld->imports);
    free(ld->images);
}

glint_status scene_file_parse(const char *name, const char *text, size_t length, int threads, glint_scene **out,
                              glint_error *err) {
    *out = NULL;
    if (!name) name = "<scene>";
    if (!text) length = 0;
    if (length > (size_t)SF_MAX_FILE_BYTES) {
        snprintf(err->message, sizeof err->message,
                 "%s: the scene is %zu bytes; at most %d bytes (256 MiB) are allowed", name, length,
                 SF_MAX_FILE_BYTES);
        return GLINT_ERR_INPUT;
    }
    if (!text) text = "";
    json_index ix;
    json_scan_error se;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    json_result jr = json_scan(text, length, &ix, &se);
    if (jr != JSON_SCAN_OK) {
        size_t line, col;
        json_line_col(text, length, se.offset, &line, &col);
        if (jr == JSON_SCAN_NOMEM)
            snprintf(err->message, sizeof err->message, "%s: out of memory while reading the scene", name);
        else snprintf(err->message, sizeof err->message, "%s:%zu:%zu: %s", name, line, col, se.message);
        return jr == JSON_SCAN_NOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    // cJSON skips a byte-order mark itself, but handing it the text after one keeps both readers aligned.
    size_t bom = length >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text + bom, length - bom, &end, 0);
    if (lane)
        trace_add(lane, &(trace_event){"JSON parse", "load", began, trace_clock(), 1,
                                       {{"bytes", (int64_t)length, NULL}}});
    sf_loader ld;
    sf_loader_init(&ld, NULL, name, threads, err);
    ld.r.text = text;
    ld.r.len = length;
    ld.r.ix = &ix;
    bool ok = false;
    jr_val top;
    if (!root) {
        // The scanner accepted the text, so this is cJSON running out of memory (or a cJSON bug).
        size_t line, col;
        json_line_col(text, length, end ? (size_t)(end - text) : 0, &line, &col);
        snprintf(err->message, sizeof err->message,
                 "%s:%zu:%zu: the JSON library could not read the scene here (out of memory?)", name, line, col);
        ld.r.status = GLINT_ERR_RENDER;
    } else if (!jr_root(&ld.r, root, &top)) {
        // jr_root wrote the message
    } else if (!(ld.scene = scene_new(name))) {
        sf_fail_oom(&ld);
    } else {
        ok = read_scene(&ld, top);
    }
    sf_loader_release(&ld);
    cJSON_Delete(root);
    json_index_free(&ix);
    if (!ok) {
        scene_free(ld.scene);
        return ld.r.status;
    }
    ld.scene->text_hash = hash_bytes(HASH_START, text, length);
    *out = ld.scene;
    return GLINT_OK;
}

// Memory ran out while a scene file was opened or read: a resource failure.
static glint_status out_of_memory_reading(const char *path, glint_error *err) {
    snprintf(err->message, sizeof err->message, "%s: out of memory while reading the scene file", path);
    return GLINT_ERR_RENDER;
}

// A mesh or model file given where a scene belongs (glint bunny.obj): GLINT_ERR_INPUT saying what a scene is and
// how to place the mesh in one, rather than a JSON syntax error at its first byte. GLINT_OK for anything else.
static glint_status model_file_given(const char *path, const char *text, size_t n, glint_error *err) {
    static const char *const models[] = {".obj", ".ply", ".gltf", ".glb", ".stl", ".fbx", ".dae", ".3ds", ".off"};
    const char *dot = strrchr(path, '.');
    size_t i = 0;
    while (i < n && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r' || text[i] == '\n')) i++;
    if (!dot || strchr(dot, '/') || (i < n && text[i] == '{' && strcmp(dot, ".gltf") != 0)) return GLINT_OK;
    size_t k = 0;
    while (k < sizeof models / sizeof models[0] && strcasecmp(dot, models[k]) != 0) k++;
    if (k == sizeof models / sizeof models[0]) return GLINT_OK;
    snprintf(err->message, sizeof err->message, "%s: a mesh or model file, not a scene: glint renders JSON scene files "
             "(docs/scene-format.md); place the mesh in one with {\"objects\": [{\"type\": \"mesh\", \"file\": "
             "\"%.200s\"}]} (Wavefront OBJ; glTF and PLY are not read yet)", path, path);
    return GLINT_ERR_INPUT;
}

glint_status scene_file_load(const char *path, int threads, glint_scene **out, glint_error *err) {
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (errno == ENOMEM) return out_of_memory_reading(path, err);
        snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, strerror(errno));
        return GLINT_ERR_INPUT;
    }
    struct stat st;
    size_t initial = 1 << 16;
    bool stat_ok = fstat(fileno(f), &st) == 0;
    if (stat_ok) {
        if (S_ISDIR(st.st_mode)) {
            fclose(f);
            snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, strerror(EISDIR));
            return GLINT_ERR_INPUT;
        }
        // A regular file's size is known: read it in one piece (files of other kinds grow the buffer).
        if (S_ISREG(st.st_mode) && st.st_size >= 0) initial = (size_t)st.st_size;
    }
    size_t n;
    int e;
    char *buf = file_read_stream(f, initial, (size_t)SF_MAX_FILE_BYTES, &n, &e);
    fclose(f);
    glint_status status = GLINT_OK;
    if (e == EFBIG) {
        snprintf(err->message, sizeof err->message, "%s: the scene file is larger than %d bytes (256 MiB)", path,
                 SF_MAX_FILE_BYTES);
        status = GLINT_ERR_INPUT;
    } else if (e == ENOMEM) {
        return out_of_memory_reading(path, err);
    } else if (e) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(e));
        status = GLINT_ERR_INPUT;
    }
    if (status == GLINT_OK) status = model_file_given(path, buf, n, err);
    if (status == GLINT_OK) status = scene_file_parse(path, buf, n, threads, out, err);
    free(buf);
    // The scene file is an input too: nothing should overwrite it.
    if (status == GLINT_OK && stat_ok && S_ISREG(st.st_mode) &&
        !scene_add_input(*out, (uint64_t)st.st_dev, (uint64_t)st.st_ino, path)) {
        scene_free(*out);
        *out = NULL;
        return out_of_memory_reading(path, err);
    }
    return status;
}
