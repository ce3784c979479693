// frame.h — the render frame: everything a render builds from a const scene (pbrt-v4's aggregate and lights):
// the acceleration structure over the scene's geometry arrays, and the integrator with its light index and
// the camera prepared for the image size. Built per render, so a change to the scene between renders counts.
#ifndef GLINT_FRAME_H
#define GLINT_FRAME_H

#include "core/status.h"
#include "accel/accel.h"
#include "integrator/integrator.h"
#include "scene/scene.h"

/// What one render of a scene reads besides the scene itself; immutable once built, shared by every thread.
typedef struct render_frame {
    accel *accel;
    integrator *integrator;
} render_frame;

/// Builds the frame of scene s (which must outlive it), the BVH as frame_accel_build does with `build` (its
/// threads: the frame is the same for any number; a nonzero *build->stop ends the BVH build early). On failure
/// returns GLINT_ERR_RENDER (GLINT_ERR_INTERRUPTED when stopped) with a message and leaves f empty.
glint_status frame_build(render_frame *f, const glint_scene *s, const integrator_options *o,
                         const accel_build_options *build, glint_error *err);
/// The acceleration structure the scene's settings choose, over its geometry (scene_geometry), built as opt says
/// (NULL: the defaults: all online CPUs, no stop) with the scene's "presplit"; NULL (message in *err) when out of
/// memory or stopped. The scene must outlive it.
accel *frame_accel_build(const glint_scene *s, const accel_build_options *opt, glint_error *err);
/// Frees what the frame built and leaves it empty.
void frame_release(render_frame *f);

#endif
