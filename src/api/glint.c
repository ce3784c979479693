// glint.c — every function of the public API (include/glint.h), and nothing else: each one checks or adapts
// its arguments and hands over to the module that does the work (as Lua keeps its whole API in lapi.c).
#include "glint.h"
#include "core/filepath.h"
#include "core/names.h"
#include "io/json_read.h"
#include "io/json_scan.h"
#include "core/thread_pool.h"
#include "core/trace.h"
#include "film/film.h"
#include "io/image_merge.h"
#include "io/image_write.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_calls.h"

#include <cjson/cJSON.h>

#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The public enums are the internal ones under other names: the values must agree.
_Static_assert((int)GLINT_FORMAT_HDR == (int)IMAGE_FORMAT_HDR && (int)GLINT_FORMAT_EXR_HALF == (int)IMAGE_FORMAT_EXR_HALF &&
                   (int)GLINT_FORMAT_PPM_ASCII == (int)IMAGE_FORMAT_PPM_ASCII && (int)GLINT_FORMAT_AUTO == 0,
               "glint_format and image_format list the formats in one order");
_Static_assert(GLINT_AOV_ALBEDO == 1u << FILM_AOV_ALBEDO && GLINT_AOV_NORMAL == 1u << FILM_AOV_NORMAL &&
                   GLINT_AOV_DEPTH == 1u << FILM_AOV_DEPTH &&
                   GLINT_AOV_SAMPLES == 1u << FILM_AOV_SAMPLES && GLINT_AOV_ALL == FILM_AOV_MASK_ALL,
               "glint_aov bit i is the film's AOV plane i");
_Static_assert((size_t)SCENE_MAX_FILE_BYTES == GLINT_MAX_SCENE_BYTES, "one scene size limit, public and private");
_Static_assert(sizeof(render_stats) == sizeof(glint_render_stats), "render_stats is glint_render_stats, field for field");

const char *glint_version(void) { return GLINT_VERSION; }

void glint_overrides_init(glint_overrides *o) {
    o->width = o->height = o->spp = o->max_depth = -1;
    o->seed = -1;
    o->accel = NULL;
    o->output_encoding = NULL;
    o->sampler = NULL;
    o->noise_threshold = -1.0;
}

// "scene load" on the calling thread's trace row, from `began` to now.
static void trace_scene_load(trace_lane *lane, int64_t began, const char *name) {
    trace_add(lane, &(trace_event){"scene load", "load", began, trace_clock(), 1, {{"file", 0, name}}});
}

glint_status glint_scene_load(const char *path, glint_scene **out, glint_error *err) {
    return glint_scene_load_with(path, NULL, out, err);
}

glint_status glint_scene_parse(const char *name, const char *text, size_t length, glint_scene **out, glint_error *err) {
    return glint_scene_parse_with(name, text, length, NULL, out, err);
}

glint_status glint_scene_load_with(const char *path, const glint_load_options *opt, glint_scene **out,
                                   glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!out) return glint_scene_parse_with(path, NULL, 0, opt, out, err);
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = scene_file_load(path, opt ? opt->threads : 0, out, err);
    if (lane) trace_scene_load(lane, began, path);
    return st;
}

glint_status glint_scene_parse_with(const char *name, const char *text, size_t length, const glint_load_options *opt,
                                    glint_scene **out, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!out) {
        snprintf(err->message, sizeof err->message, "glint_scene_parse: no place to store the scene");
        return GLINT_ERR_INPUT;
    }
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = scene_file_parse(name ? name : "<scene>", text, text ? length : 0, opt ? opt->threads : 0, out, err);
    if (lane) trace_scene_load(lane, began, name ? name : "<scene>");
    return st;
}

glint_status glint_scene_override(glint_scene *scene, const glint_overrides *o, glint_error *err) {
    glint_error scratch;
    scene_overrides so = {o->width, o->height,          o->spp,     o->max_depth,       o->seed,
                          o->accel, o->output_encoding, o->sampler, o->noise_threshold};
    return scene_override(scene, &so, err ? err : &scratch);
}

void glint_scene_size(const glint_scene *scene, int *width, int *height) {
    *width = scene->settings.width;
    *height = scene->settings.height;
}

size_t glint_scene_warning_count(const glint_scene *scene) { return scene ? scene->warning_count : 0; }

const char *glint_scene_warning(const glint_scene *scene, size_t i) {
    return scene && i < scene->warning_count ? scene->warnings[i] : NULL;
}

bool glint_scene_reads_file(const glint_scene *scene, const char *path) {
    return scene && scene_reads_file(scene, path);
}

void glint_scene_free(glint_scene *scene) { scene_free(scene); }

// A token is one atomic flag: requesting it is a store, which a signal handler may do.
struct glint_cancel {
    atomic_int requested;
};

// Renders `scene` with this render's overrides applied to a copy of it (the scene itself is not changed): the
// copy shares every array but the warnings, which an override may add to.
static glint_status render_overridden(const glint_scene *scene, const glint_overrides *o, const render_options *ro,
                                      glint_progress_fn progress, void *user, glint_image **out, render_stats *rs,
                                      glint_error *err) {
    glint_scene copy = *scene;
    copy.warnings = NULL;
    copy.warning_count = copy.capacity.warnings = 0;
    scene_overrides so = {o->width, o->height,          o->spp,     o->max_depth,       o->seed,
                          o->accel, o->output_encoding, o->sampler, o->noise_threshold};
    glint_status st = scene_override(&copy, &so, err);
    if (st == GLINT_OK) st = render_scene(&copy, ro, progress, user, out, rs, err);
    for (size_t i = 0; i < copy.warning_count; i++) free(copy.warnings[i]);
    free(copy.warnings);
    return st;
}

glint_status glint_render(const glint_scene *scene, const glint_render_options *opt, glint_progress_fn progress,
                          void *user, glint_image **out, glint_render_stats *stats, glint_error *err) {
    glint_error scratch;
    glint_image *kept = NULL;
    if (!out) out = &kept; // the caller wants rgb_out alone
    *out = NULL;
    if (!scene) return status_fail(err ? err : &scratch, GLINT_ERR_INPUT, "glint_render: no scene");
    render_options ro = {.threads = opt ? opt->threads : 0, .time_limit = opt ? opt->time_limit : 0.0};
    if (opt) {
        memcpy(ro.region, opt->region, sizeof ro.region);
        ro.live_image = opt->live_image;
        ro.live_user = opt->live_user;
        ro.checkpoint = opt->checkpoint;
        ro.resume = opt->resume;
        ro.cancel = opt->cancel ? &opt->cancel->requested : NULL;
    }
    ro.aovs = opt ? opt->aovs : 0u;
    render_stats rs;
    glint_status st = opt && opt->overrides
                          ? render_overridden(scene, opt->overrides, &ro, progress, user, out, stats ? &rs : NULL,
                                              err ? err : &scratch)
                          : render_scene(scene, &ro, progress, user, out, stats ? &rs : NULL, err ? err : &scratch);
    if (*out && opt && opt->rgb_out)
        memcpy(opt->rgb_out, (*out)->rgb, (size_t)(*out)->width * (size_t)(*out)->height * 3 * sizeof(float));
    film_image_free(kept);
    if (stats) *stats = (glint_render_stats){rs.wall_seconds, rs.build_seconds, rs.render_seconds, rs.samples, rs.rays,
                                             rs.shadow_rays, rs.discarded_samples, rs.samples_resumed, rs.bvh_nodes,
                                             rs.bvh_leaves, rs.bvh_depth, rs.threads, rs.spp, rs.spp_done};
    return st;
}

// ---------------------------------------------------------------------------------------------
// Scenes built call by call: every value goes to the scene file's reader as JSON text (scene/scene_calls.h)

// Named values: one JSON object. `failed`: a setter ran out of memory, and the call that uses it says so.
struct glint_params {
    cJSON *json;
    bool failed;
};

glint_params *glint_params_new(void) {
    glint_params *p = malloc(sizeof *p);
    if (!p) return NULL;
    if (!(p->json = cJSON_CreateObject())) {
        free(p);
        return NULL;
    }
    p->failed = false;
    return p;
}

void glint_params_free(glint_params *p) {
    if (!p) return;
    cJSON_Delete(p->json);
    free(p);
}

// Sets key to v (taken), replacing a value it had; marks p failed when v is NULL (out of memory).
static void params_set(glint_params *p, const char *key, cJSON *v) {
    if (!p) {
        cJSON_Delete(v);
        return;
    }
    if (!v || !key) {
        cJSON_Delete(v);
        p->failed = true;
        return;
    }
    if (cJSON_GetObjectItemCaseSensitive(p->json, key) ? !cJSON_ReplaceItemInObjectCaseSensitive(p->json, key, v)
                                                       : !cJSON_AddItemToObject(p->json, key, v)) {
        cJSON_Delete(v);
        p->failed = true;
    }
}

void glint_params_number(glint_params *p, const char *key, double v) { params_set(p, key, cJSON_CreateNumber(v)); }

void glint_params_numbers(glint_params *p, const char *key, const double *v, size_t n) {
    cJSON *a = cJSON_CreateArray();
    for (size_t i = 0; a && i < n; i++) {
        cJSON *x = cJSON_CreateNumber(v[i]);
        if (!x || !cJSON_AddItemToArray(a, x)) {
            cJSON_Delete(x);
            cJSON_Delete(a);
            a = NULL;
        }
    }
    params_set(p, key, a);
}

void glint_params_string(glint_params *p, const char *key, const char *s) {
    params_set(p, key, s ? cJSON_CreateString(s) : cJSON_CreateNull());
}

void glint_params_bool(glint_params *p, const char *key, bool v) { params_set(p, key, cJSON_CreateBool(v)); }

void glint_params_object(glint_params *p, const char *key, const glint_params *value) {
    if (value && value->failed && p) p->failed = true;
    params_set(p, key, value ? cJSON_Duplicate(value->json, 1) : NULL);
}

void glint_params_append(glint_params *p, const char *key, const glint_params *item) {
    if (!p) return;
    cJSON *copy = item ? cJSON_Duplicate(item->json, 1) : NULL;
    cJSON *array = key ? cJSON_GetObjectItemCaseSensitive(p->json, key) : NULL;
    if (item && item->failed) p->failed = true;
    if (array && cJSON_IsArray(array)) {
        if (!copy || !cJSON_AddItemToArray(array, copy)) {
            cJSON_Delete(copy);
            p->failed = true;
        }
        return;
    }
    cJSON *fresh = cJSON_CreateArray();
    if (fresh && copy && cJSON_AddItemToArray(fresh, copy)) {
        params_set(p, key, fresh);
        return;
    }
    cJSON_Delete(copy);
    cJSON_Delete(fresh);
    p->failed = true;
}

// Parses JSON text checked by glint's own scanner first, so that its syntax errors read as a scene file's do
// ("line:col: ..."), with `call` in front; *out is the tree.
static glint_status params_parse_text(const char *call, const char *json, cJSON **out, glint_error *err) {
    *out = NULL;
    if (!json) return status_fail(err, GLINT_ERR_INPUT, "%s: no JSON text", call);
    size_t n = strlen(json);
    json_index ix;
    json_scan_error se;
    json_result r = json_scan(json, n, &ix, &se);
    if (r == JSON_SCAN_NOMEM) return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory", call);
    if (r != JSON_SCAN_OK) {
        size_t line, col;
        json_line_col(json, n, se.offset, &line, &col);
        return status_fail(err, GLINT_ERR_INPUT, "%s:%zu:%zu: %s", call, line, col, se.message);
    }
    json_index_free(&ix);
    if (!(*out = cJSON_ParseWithLength(json, n))) return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory", call);
    return GLINT_OK;
}

glint_status glint_params_json(glint_params *p, const char *key, const char *json, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!p || !key) return status_fail(err, GLINT_ERR_INPUT, "glint_params_json: no parameters or no key");
    cJSON *v;
    glint_status st = params_parse_text("glint_params_json", json, &v, err);
    if (st != GLINT_OK) return st;
    params_set(p, key, v);
    return p->failed ? status_fail(err, GLINT_ERR_RENDER, "glint_params_json: out of memory") : GLINT_OK;
}

glint_status glint_params_parse(const char *json, glint_params **out, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!out) return status_fail(err, GLINT_ERR_INPUT, "glint_params_parse: no place to store the parameters");
    *out = NULL;
    cJSON *v;
    glint_status st = params_parse_text("glint_params_parse", json, &v, err);
    if (st != GLINT_OK) return st;
    if (!cJSON_IsObject(v)) {
        cJSON_Delete(v);
        return status_fail(err, GLINT_ERR_INPUT, "glint_params_parse: expected a JSON object");
    }
    glint_params *p = malloc(sizeof *p);
    if (!p) {
        cJSON_Delete(v);
        return status_fail(err, GLINT_ERR_RENDER, "glint_params_parse: out of memory");
    }
    *p = (glint_params){v, false};
    *out = p;
    return GLINT_OK;
}

glint_status glint_scene_new(const char *name, glint_scene **out, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!out) return status_fail(err, GLINT_ERR_INPUT, "glint_scene_new: no place to store the scene");
    if (!(*out = scene_new(name ? name : "<scene>")))
        return status_fail(err, GLINT_ERR_RENDER, "glint_scene_new: out of memory");
    return GLINT_OK;
}

// A copy of v whose numbers are spelled as a person writes them (jr_number_text: 0.5, 1e39, 1e999 for an infinity),
// so that a message's "got ..." quotes the value the caller gave as a file would; NULL when out of memory.
static cJSON *printable(const cJSON *v) {
    if (cJSON_IsNumber(v)) {
        char text[64];
        jr_number_text(v->valuedouble, text, sizeof text);
        return cJSON_CreateRaw(text);
    }
    if (!cJSON_IsArray(v) && !cJSON_IsObject(v)) return cJSON_Duplicate(v, 0);
    cJSON *copy = cJSON_IsArray(v) ? cJSON_CreateArray() : cJSON_CreateObject();
    for (const cJSON *e = v->child; copy && e; e = e->next) {
        cJSON *c = printable(e);
        bool added = c && (cJSON_IsArray(v) ? cJSON_AddItemToArray(copy, c) : cJSON_AddItemToObject(copy, e->string, c));
        if (!added) {
            cJSON_Delete(c);
            cJSON_Delete(copy);
            copy = NULL;
        }
    }
    return copy;
}

// Hands the values of p to the scene file's reader as `part` of the scene.
static glint_status scene_call(glint_scene *s, scene_call_part part, const char *call, const char *name,
                               const glint_params *p, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!s) return status_fail(err, GLINT_ERR_INPUT, "%s: no scene", call);
    if (!p) return status_fail(err, GLINT_ERR_INPUT, "%s: no parameters", call);
    if (p->failed) return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory while the parameters were set", call);
    cJSON *spelled = printable(p->json);
    char *text = spelled ? cJSON_PrintUnformatted(spelled) : NULL;
    cJSON_Delete(spelled);
    if (!text) return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory", call);
    glint_status st = scene_call_read(s, part, call, name, text, strlen(text), err);
    cJSON_free(text);
    return st;
}

glint_status glint_scene_set_render(glint_scene *s, const glint_params *values, glint_error *err) {
    return scene_call(s, SCENE_CALL_RENDER, "glint_scene_set_render", NULL, values, err);
}

glint_status glint_scene_set_camera(glint_scene *s, const glint_params *values, glint_error *err) {
    return scene_call(s, SCENE_CALL_CAMERA, "glint_scene_set_camera", NULL, values, err);
}

glint_status glint_scene_add_texture(glint_scene *s, const char *name, const glint_params *values, glint_error *err) {
    return scene_call(s, SCENE_CALL_TEXTURE, "glint_scene_add_texture", name, values, err);
}

glint_status glint_scene_add_material(glint_scene *s, const char *name, const glint_params *values,
                                      glint_error *err) {
    return scene_call(s, SCENE_CALL_MATERIAL, "glint_scene_add_material", name, values, err);
}

glint_status glint_scene_add_object(glint_scene *s, const glint_params *values, glint_error *err) {
    return scene_call(s, SCENE_CALL_OBJECT, "glint_scene_add_object", NULL, values, err);
}

glint_status glint_scene_add_light(glint_scene *s, const glint_params *values, glint_error *err) {
    return scene_call(s, SCENE_CALL_LIGHT, "glint_scene_add_light", NULL, values, err);
}

glint_status glint_scene_add_mesh(glint_scene *s, const char *name, const glint_mesh_data *m, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!s || !m) return status_fail(err, GLINT_ERR_INPUT, "glint_scene_add_mesh: no %s", s ? "mesh" : "scene");
    scene_mesh_arrays a = {m->vertex_count,  m->positions,      m->normals,   m->uvs,           m->triangle_count,
                           m->indices,       m->face_materials, m->materials, m->material_count, m->flat};
    return scene_call_add_mesh(s, "glint_scene_add_mesh", name, &a, err);
}

glint_status glint_scene_add_image(glint_scene *s, const char *name, const glint_pixels *px,
                                   const glint_params *options, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    const char *call = "glint_scene_add_image";
    if (!s || !px) return status_fail(err, GLINT_ERR_INPUT, "%s: no %s", call, s ? "pixels" : "scene");
    if (options && options->failed)
        return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory while the options were set", call);
    cJSON *spelled = options ? printable(options->json) : NULL;
    char *text = spelled ? cJSON_PrintUnformatted(spelled) : NULL;
    cJSON_Delete(spelled);
    if (options && !text) return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory", call);
    scene_pixels sp = {px->width, px->height, px->channels, px->values, px->bytes};
    glint_status st = scene_call_add_image(s, call, name, &sp, text, text ? strlen(text) : 0, err);
    cJSON_free(text);
    return st;
}

glint_status glint_image_from_rgb(int width, int height, const float *rgb, const char *output_encoding,
                                  glint_image **out, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    const char *call = "glint_image_from_rgb";
    if (!out) return status_fail(err, GLINT_ERR_INPUT, "%s: no place to store the image", call);
    *out = NULL;
    if (width < 1 || height < 1 || width > SCENE_MAX_DIMENSION || height > SCENE_MAX_DIMENSION || !rgb)
        return status_fail(err, GLINT_ERR_INPUT, "%s: %d x %d pixels%s; expected 1 to %d a side", call, width, height,
                           rgb ? "" : " and no values", SCENE_MAX_DIMENSION);
    int encoding = output_encoding ? names_find(output_transform_names, TRANSFORM_COUNT, output_encoding)
                                   : (int)TRANSFORM_SRGB;
    if (encoding < 0)
        return status_fail(err, GLINT_ERR_INPUT, "%s: unknown encoding '%s', expected linear, gamma2 or srgb", call,
                           output_encoding);
    glint_image *img = film_image_new(width, height, (output_transform)encoding);
    if (!img) return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory", call);
    memcpy(img->rgb, rgb, (size_t)width * (size_t)height * 3 * sizeof(float));
    *out = img;
    return GLINT_OK;
}

glint_cancel *glint_cancel_new(void) {
    glint_cancel *c = malloc(sizeof *c);
    if (c) atomic_init(&c->requested, 0);
    return c;
}

void glint_cancel_request(glint_cancel *c) {
    if (c) atomic_store(&c->requested, 1);
}

bool glint_cancel_requested(const glint_cancel *c) { return c && atomic_load(&c->requested) != 0; }

void glint_cancel_reset(glint_cancel *c) {
    if (c) atomic_store(&c->requested, 0);
}

void glint_cancel_free(glint_cancel *c) { free(c); }

glint_status glint_image_write(const glint_image *img, const char *path, glint_format format, glint_error *err) {
    glint_error scratch;
    return image_write(img, path, (image_format)format, err ? err : &scratch);
}

glint_status glint_image_write_aov(const glint_image *img, glint_aov aov, const char *path, glint_error *err) {
    glint_error scratch;
    int index = -1;
    for (int i = 0; i < FILM_AOV_COUNT; i++)
        if ((unsigned)aov == 1u << i) index = i;
    return image_write_aov(img, index, path, err ? err : &scratch);
}

glint_status glint_image_check_path(const char *path, glint_format format, glint_error *err) {
    glint_error scratch;
    return image_check_path(path, (image_format)format, err ? err : &scratch);
}

void glint_image_info(const glint_image *img, int *width, int *height, const float **rgb) {
    *width = img->width;
    *height = img->height;
    *rgb = img->rgb;
}

uint8_t glint_image_byte(const glint_image *img, int x, int y, int c) {
    return film_encode(img->rgb[((size_t)y * (size_t)img->width + (size_t)x) * 3u + (size_t)c], img->transform);
}

const float *glint_image_aov(const glint_image *img, glint_aov aov, int *channels) {
    for (int i = 0; i < FILM_AOV_COUNT; i++)
        if ((unsigned)aov == 1u << i && img && img->aov[i]) {
            if (channels) *channels = film_aov_channels(i);
            return img->aov[i];
        }
    if (channels) *channels = 0;
    return NULL;
}

void glint_image_rgb8(const glint_image *img, uint8_t *rgb) { film_encode_image(img, rgb); }

void glint_image_free(glint_image *img) { film_image_free(img); }

glint_status glint_merge(const char *output, const char *const *parts, size_t count, glint_error *err) {
    glint_error scratch;
    return image_merge(output, parts, count, err ? err : &scratch);
}

glint_trace *glint_trace_new(void) { return trace_new(); }

glint_status glint_trace_attach(glint_trace *t, const char *thread_name, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    trace_lane *now = trace_current();
    if (!t || (now && trace_lane_owner(now) == t)) { // detach, or stay on the row the thread has
        if (!t) trace_set_current(NULL);
        return GLINT_OK;
    }
    trace_lane *lane = trace_lane_open(t, thread_name ? thread_name : "thread");
    if (!lane) {
        snprintf(err->message, sizeof err->message, "out of memory for a row of the trace");
        return GLINT_ERR_RENDER;
    }
    trace_set_current(lane);
    return GLINT_OK;
}

int glint_cpu_count(void) { return thread_pool_online_cpus(); }

bool glint_path_same_target(const char *a, const char *b) { return a && b && filepath_same_target(a, b); }

glint_status glint_trace_check_path(const char *path, glint_error *err) {
    glint_error scratch;
    return image_check_file(path, err ? err : &scratch);
}

static int write_trace_file(FILE *f, const void *user, char *why, size_t why_size) {
    (void)why;
    (void)why_size;
    return trace_write_json(user, f);
}

glint_status glint_trace_write(glint_trace *t, const char *path, glint_error *err) {
    glint_error scratch;
    if (!err) err = &scratch;
    if (!t || !path) {
        snprintf(err->message, sizeof err->message, "glint_trace_write: no %s", t ? "file name" : "trace");
        return GLINT_ERR_INPUT;
    }
    if (!trace_complete(t)) {
        snprintf(err->message, sizeof err->message, "%s: cannot write the trace: memory ran out while it was "
                 "recorded, so events are missing", path);
        return GLINT_ERR_RENDER;
    }
    return image_write_file(path, write_trace_file, t, err);
}

void glint_trace_free(glint_trace *t) { trace_free(t); }
