// whitted.h — the Whitted integrators' constructor, for the chooser (integrator.c).
#ifndef GLINT_WHITTED_H
#define GLINT_WHITTED_H

#include "core/status.h"
#include "integrator/integrator_common.h"

/// The Whitted integrator (paper or colour mode, as the scene says).
integrator *whitted_create(const glint_scene *s, const accel *a, glint_error *err);

#endif
