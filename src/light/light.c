// light.c — light names; lights are evaluated by the integrators.
#include "light/light.h"

const char *light_kind_name(light_kind kind) {
    switch (kind) {
    case LIGHT_AMBIENT: return "ambient";
    case LIGHT_POINT: return "point";
    case LIGHT_DIRECTIONAL: return "directional";
    case LIGHT_SPOT: return "spot";
    }
    return "?";
}
