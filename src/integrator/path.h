// path.h — the path tracer's constructor, for the chooser (integrator.c).
#ifndef GLINT_PATH_H
#define GLINT_PATH_H

#include "core/status.h"
#include "integrator/integrator_common.h"

#include <stdbool.h>

/// The path tracer, as the render's options say (o may be NULL: the defaults; the tests' knobs in
/// integrator_options).
integrator *path_create(const glint_scene *s, const accel *a, const integrator_options *o, glint_error *err);

#endif
