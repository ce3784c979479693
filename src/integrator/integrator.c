// integrator.c — choosing and building the integrator a scene asks for, and freeing it: the chooser, which calls
// down into the integrators (path.c, whitted.c) and nothing calls back.
#include "integrator/integrator.h"
#include "integrator/path.h"
#include "integrator/whitted.h"

#include <stddef.h>
#include <stdlib.h>

integrator *integrator_create(const glint_scene *s, const accel *a, const integrator_options *o, glint_error *err) {
    switch (s->settings.integrator) {
    case INTEGRATOR_WHITTED: return whitted_create(s, a, err);
    case INTEGRATOR_PATH: return path_create(s, a, o, err);
    }
    return NULL;
}

void integrator_free(integrator *it) {
    if (!it) return;
    if (it->release) it->release(it);
    else free(it);
}
