// frame.c — building the render frame: the scene's geometry value (scene_geometry) handed to the accel with the
// build options, then the integrator over the scene and that accel.
#include "render/frame.h"
#include "core/trace.h"

#include <stdio.h>
#include <stdlib.h>

// "BVH build" on the trace: what was built over how much.
static void trace_accel_build(trace_lane *lane, const glint_scene *s, int64_t began) {
    size_t triangles = 0;
    for (size_t i = 0; i < s->mesh_count; i++) triangles += s->meshes[i].geometry.triangle_count;
    accel_kind k = s->settings.accel;
    trace_add(lane, &(trace_event){k == ACCEL_NONE ? "accel build" : "BVH build", "render", began, trace_clock(), 6,
                                   {{"accel", 0, accel_kind_names[k]},
                                    {"spheres", (int64_t)(s->sphere_count + s->moving_sphere_count), NULL},
                                    {"quads", (int64_t)s->quad_count, NULL},
                                    {"meshes", (int64_t)s->mesh_count, NULL},
                                    {"triangles", (int64_t)triangles, NULL},
                                    {"instances", (int64_t)s->instance_count, NULL}}});
}

accel *frame_accel_build(const glint_scene *s, const accel_build_options *opt, glint_error *err) {
    // The scene's "presplit" and "spatial_splits" join the caller's options; the rest (threads, stop, tests' knobs)
    // are the caller's.
    accel_build_options o = opt ? *opt : (accel_build_options){0};
    o.no_presplit = o.no_presplit || s->settings.no_presplit;
    o.no_spatial = o.no_spatial || s->settings.no_spatial;
    const mesh **meshes = s->mesh_count ? malloc(s->mesh_count * sizeof *meshes) : NULL;
    if (s->mesh_count && !meshes) {
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    geometry_arrays g = scene_geometry(s, meshes);
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    accel *a = accel_build(&g, s->settings.accel, &o, err);
    if (lane) trace_accel_build(lane, s, began);
    free(meshes); // accel_build keeps a copy of the list
    return a;
}

glint_status frame_build(render_frame *f, const glint_scene *s, const integrator_options *o,
                         const accel_build_options *build, glint_error *err) {
    f->accel = NULL;
    f->integrator = NULL;
    f->accel = frame_accel_build(s, build, err);
    if (!f->accel) return build && build->stop && atomic_load(build->stop) ? GLINT_ERR_INTERRUPTED : GLINT_ERR_RENDER;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    f->integrator = integrator_create(s, f->accel, o, err);
    // The light index, the environment's sampling distribution and the camera: a step of its own on the timeline.
    if (lane) trace_add(lane, &(trace_event){.name = "integrator setup", .category = "render", .start = began,
                                             .end = trace_clock()});
    if (!f->integrator) {
        frame_release(f);
        return GLINT_ERR_RENDER;
    }
    return GLINT_OK;
}

void frame_release(render_frame *f) {
    integrator_free(f->integrator);
    accel_free(f->accel);
    f->integrator = NULL;
    f->accel = NULL;
}
