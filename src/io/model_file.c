// model_file.c — the model records' helpers that the readers share (model_file.h).
#include "io/model_file.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

model_format model_format_of(const char *path) {
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash)) return MODEL_FORMAT_NONE;
    char ext[6] = {0};
    size_t n = strlen(dot + 1);
    if (n == 0 || n >= sizeof ext) return MODEL_FORMAT_NONE;
    for (size_t i = 0; i < n; i++) ext[i] = (char)tolower((unsigned char)dot[1 + i]);
    if (strcmp(ext, "ply") == 0) return MODEL_FORMAT_PLY;
    if (strcmp(ext, "gltf") == 0) return MODEL_FORMAT_GLTF;
    if (strcmp(ext, "glb") == 0) return MODEL_FORMAT_GLB;
    return MODEL_FORMAT_NONE;
}

static void free_mesh_list(model_file *m) {
    for (size_t i = 0; i < m->mesh_count; i++) mesh_free(&m->meshes[i].geometry);
    free(m->meshes);
}

void model_file_free(model_file *m) {
    if (!m) return;
    free_mesh_list(m);
    free(m->placements);
    for (size_t i = 0; i < m->material_count; i++) free(m->materials[i].name);
    free(m->materials);
    for (size_t i = 0; i < m->image_count; i++) {
        free(m->images[i].path);
        free(m->images[i].data);
        free(m->images[i].name);
    }
    free(m->images);
    for (size_t i = 0; i < m->light_count; i++) free(m->lights[i].name);
    free(m->lights);
    for (size_t i = 0; i < m->camera_count; i++) free(m->cameras[i].name);
    free(m->cameras);
    for (size_t i = 0; i < m->input_count; i++) free(m->inputs[i].path);
    free(m->inputs);
    memset(m, 0, sizeof *m);
}

bool model_file_add_input(model_file *m, const struct stat *st, const char *path) {
    for (size_t i = 0; i < m->input_count; i++)
        if (m->inputs[i].dev == (uint64_t)st->st_dev && m->inputs[i].ino == (uint64_t)st->st_ino) return true;
    model_input *grown = realloc(m->inputs, (m->input_count + 1) * sizeof *grown);
    if (!grown) return false;
    m->inputs = grown;
    char *copy = strdup(path);
    if (!copy) return false;
    m->inputs[m->input_count++] = (model_input){(uint64_t)st->st_dev, (uint64_t)st->st_ino, copy};
    return true;
}

void model_file_warn(model_warning_fn warn, void *user, const char *path, const char *fmt, va_list ap) {
    if (!warn) return;
    char msg[1024], prefix[400];
    snprintf(prefix, sizeof prefix, "%s: warning: ", path);
    status_vformat(msg, sizeof msg, prefix, fmt, ap);
    warn(msg, user);
}
