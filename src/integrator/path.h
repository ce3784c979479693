// path.h — the path tracer's constructor, for the chooser (integrator.c).
#ifndef GLINT_PATH_H
#define GLINT_PATH_H

#include "core/status.h"
#include "integrator/integrator_common.h"

#include <stdbool.h>

/// The path tracer; `sample_area_lights` false turns off next-event estimation towards emissive surfaces;
/// `light_sampling_only` (tests) leaves the glossy and diffuse vertices of the microfacet materials to light
/// sampling alone (integrator_options).
integrator *path_create(const glint_scene *s, const accel *a, bool sample_area_lights, bool light_sampling_only,
                        glint_error *err);

#endif
