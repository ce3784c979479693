// path.h — the path tracer's constructor, for the chooser (integrator.c).
#ifndef GLINT_PATH_H
#define GLINT_PATH_H

#include "core/status.h"
#include "integrator/integrator_common.h"

#include <stdbool.h>

/// The path tracer; `sample_area_lights` false turns off next-event estimation towards emissive surfaces.
integrator *path_create(const glint_scene *s, const accel *a, bool sample_area_lights, bool use_light_tree,
                        glint_error *err);

#endif
