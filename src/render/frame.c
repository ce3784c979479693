// frame.c — building the render frame: the scene's geometry handed to the accel as plain arrays, then the
// integrator over the scene and that accel.
#include "render/frame.h"

#include <stdio.h>
#include <stdlib.h>

accel *frame_accel_build(const glint_scene *s, int threads, const atomic_int *stop, glint_error *err) {
    // The accel sees meshes as bare triangle lists: their material slots are the scene's business.
    const mesh **meshes = s->mesh_count ? malloc(s->mesh_count * sizeof *meshes) : NULL;
    if (s->mesh_count && !meshes) {
        snprintf(err->message, sizeof err->message, "out of memory building the acceleration structure");
        return NULL;
    }
    for (size_t i = 0; i < s->mesh_count; i++) meshes[i] = &s->meshes[i].geometry;
    accel_input in = {.spheres = s->spheres,
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
                      .time1 = s->camera.shutter_close,
                      .stop = stop,
                      .threads = threads};
    accel *a = accel_build(&in, s->settings.accel, err);
    free(meshes); // accel_build keeps a copy of the list
    return a;
}

glint_status frame_build(render_frame *f, const glint_scene *s, const integrator_options *o, int threads,
                         const atomic_int *stop, glint_error *err) {
    f->accel = NULL;
    f->integrator = NULL;
    f->accel = frame_accel_build(s, threads, stop, err);
    if (!f->accel) return stop && atomic_load(stop) ? GLINT_ERR_INTERRUPTED : GLINT_ERR_RENDER;
    f->integrator = integrator_create(s, f->accel, o, err);
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
