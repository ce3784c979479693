// load_json.c — the strict JSON scene reader.
#include "scene/scene.h"

#include <stdio.h>

glint_status glint_scene_parse(const char *name, const char *text, size_t length, glint_scene **out, glint_error *err) {
    (void)text; (void)length;
    *out = NULL;
    snprintf(err->message, sizeof err->message, "%s: scene parsing is not written yet", name);
    return GLINT_ERR_INPUT;
}

glint_status glint_scene_load(const char *path, glint_scene **out, glint_error *err) {
    return glint_scene_parse(path, "", 0, out, err);
}
