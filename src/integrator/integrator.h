// integrator.h — the light-transport algorithms (the paper's and the colour Whitted ray tracer, the path
// tracer) behind one interface: built per render from a const scene and the acceleration structure, each
// renders "these samples of this tile" into the film. The render loop (render/) knows nothing more of them.
// The interface itself (tile_pass, the integrator struct) is in integrator_common.h; this is the chooser.
#ifndef GLINT_INTEGRATOR_H
#define GLINT_INTEGRATOR_H

#include "core/status.h"
#include "integrator/integrator_common.h"

#include <stdbool.h>

/// The integrator the scene's settings choose, reading s and a (both must outlive it). NULL, with a message
/// in *err, when out of memory.
integrator *integrator_create(const glint_scene *s, const accel *a, const integrator_options *o, glint_error *err);
/// Frees an integrator (NULL is allowed).
void integrator_free(integrator *it);

#endif
