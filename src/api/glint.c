// glint.c — every function of the public API (include/glint.h), and nothing else: each one checks or adapts
// its arguments and hands over to the module that does the work (as Lua keeps its whole API in lapi.c).
#include "glint.h"
#include "core/filepath.h"
#include "core/thread_pool.h"
#include "core/trace.h"
#include "film/film.h"
#include "io/image_merge.h"
#include "io/image_write.h"
#include "render/render.h"
#include "scene/scene.h"

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

glint_status glint_render(const glint_scene *scene, const glint_render_options *opt, glint_progress_fn progress,
                          void *user, glint_image **out, glint_render_stats *stats, glint_error *err) {
    glint_error scratch;
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
    glint_status st = render_scene(scene, &ro, progress, user, out, stats ? &rs : NULL, err ? err : &scratch);
    if (stats) *stats = (glint_render_stats){rs.wall_seconds, rs.build_seconds, rs.render_seconds, rs.samples, rs.rays,
                                             rs.shadow_rays, rs.discarded_samples, rs.samples_resumed, rs.bvh_nodes,
                                             rs.bvh_leaves, rs.bvh_depth, rs.threads, rs.spp, rs.spp_done};
    return st;
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
