// ply_fast.c — PLY headers checked against the file before anything reads the body, and glint's own reader of the
// simplest binary layout (ply_fast.h).
#include "io/ply_fast.h"

#include "core/file_read.h"
#include "core/filepath.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static glint_status fail_oom(const char *path, glint_error *err) {
    return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory while reading the model", path);
}

static void warn(model_warning_fn fn, void *user, const char *path, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void warn(model_warning_fn fn, void *user, const char *path, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    model_file_warn(fn, user, path, fmt, ap);
    va_end(ap);
}

// The bytes of a PLY scalar type, 0 for an unknown name.
static unsigned ply_type_size(const char *t) {
    static const struct { const char *name; unsigned size; } types[] = {
        {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
        {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
        {"double", 8}, {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0) return types[i].size;
    return 0;
}

// The offset slot of vertex property `name` in the layout, or NULL when glint does not use it.
static int *ply_slot(ply_layout *l, const char *name) {
    static const char *const pos[] = {"x", "y", "z"}, *const nrm[] = {"nx", "ny", "nz"};
    static const char *const uv[][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
    for (int k = 0; k < 3; k++) {
        if (strcmp(name, pos[k]) == 0) return &l->pos[k];
        if (strcmp(name, nrm[k]) == 0) return &l->nrm[k];
    }
    for (int i = 0; i < 4; i++)
        for (int k = 0; k < 2; k++)
            if (strcmp(name, uv[i][k]) == 0) return &l->uv[k];
    return NULL;
}

glint_status ply_check_header(const char *path, ply_layout *layout, glint_error *err) {
    *layout = (ply_layout){false, 0, 0, 0, 0, {-1, -1, -1}, {-1, -1, -1}, {-1, -1}};
    struct stat st;
    int problem;
    FILE *f = filepath_open_regular(path, &st, &problem);
    if (!f) return status_fail(err, GLINT_ERR_INPUT, "%s: cannot open: %s", path, filepath_problem_text(problem));
    char *text = malloc(PLY_MAX_HEADER + 1);
    if (!text) {
        fclose(f);
        return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory while reading the model", path);
    }
    size_t n = fread(text, 1, PLY_MAX_HEADER, f);
    fclose(f);
    text[n] = '\0';
    char *end = strstr(text, "end_header");
    glint_status result = GLINT_OK;
    if (strncmp(text, "ply", 3) != 0 || !end) {
        free(text);
        return GLINT_OK; // not a PLY header glint can read: assimp says what is wrong
    }
    char *body = strchr(end, '\n');
    double header_bytes = body ? (double)(body + 1 - text) : (double)n, body_bytes = (double)st.st_size - header_bytes;
    *end = '\0';
    bool ascii = strstr(text, "format ascii") != NULL;
    // The fast layout, checked statement by statement: elements seen (1 vertex, 2 face), properties of the face.
    const uint32_t one = 1;
    unsigned char little;
    memcpy(&little, &one, 1);
    bool fast = little && strstr(text, "format binary_little_endian 1.0") != NULL;
    int element = 0, face_props = 0;
    double need = 0.0, per_item = 0.0, count = 0.0;
    char name[64] = "", current[64] = "";
    char *save = NULL;
    for (char *line = strtok_r(text, "\r\n", &save); line; line = strtok_r(NULL, "\r\n", &save)) {
        char a[32], b[32], c[32];
        unsigned long long declared;
        if (sscanf(line, "element %63s %llu", name, &declared) == 2) {
            need += count * per_item;
            count = (double)declared;
            per_item = 0.0;
            snprintf(current, sizeof current, "%s", name);
            if (declared > (unsigned long long)INT32_MAX) {
                result = status_fail(err, GLINT_ERR_INPUT, "%s: the header declares %llu elements \"%s\"; at most 2^31 - 1",
                                     path, declared, current);
                break;
            }
            element++;
            if (element == 1 && strcmp(name, "vertex") == 0) layout->vertices = (uint32_t)declared;
            else if (element == 2 && strcmp(name, "face") == 0) layout->faces = (uint32_t)declared;
            else fast = false;
        } else if (sscanf(line, "property list %31s %31s %31s", a, b, c) == 3) {
            per_item += ascii ? 2.0 : (double)ply_type_size(a);
            fast = fast && element == 2 && ++face_props == 1 && (strcmp(a, "uchar") == 0 || strcmp(a, "uint8") == 0) &&
                   ply_type_size(b) == 4 && strncmp(b, "float", 5) != 0 &&
                   (strcmp(c, "vertex_indices") == 0 || strcmp(c, "vertex_index") == 0);
        } else if (sscanf(line, "property %31s %31s", a, b) == 2) {
            per_item += ascii ? 2.0 : (double)ply_type_size(a);
            if (element != 1 || !(strcmp(a, "float") == 0 || strcmp(a, "float32") == 0)) {
                fast = false;
            } else {
                int *slot = ply_slot(layout, b);
                if (slot && *slot >= 0) fast = false; // the same property twice
                if (slot) *slot = (int)layout->stride;
                layout->stride += 4;
            }
        } else if (strncmp(line, "ply", 3) != 0 && strncmp(line, "format", 6) != 0 && strncmp(line, "comment", 7) != 0 &&
                   strncmp(line, "obj_info", 8) != 0) {
            fast = false; // a statement glint does not know: assimp reads the file
        }
    }
    // Normals come in threes and texture coordinates in pairs, or not at all.
    bool some_n = layout->nrm[0] >= 0 || layout->nrm[1] >= 0 || layout->nrm[2] >= 0;
    bool all_n = layout->nrm[0] >= 0 && layout->nrm[1] >= 0 && layout->nrm[2] >= 0;
    layout->fast = fast && element == 2 && face_props == 1 && layout->pos[0] >= 0 && layout->pos[1] >= 0 &&
                   layout->pos[2] >= 0 && some_n == all_n && (layout->uv[0] >= 0) == (layout->uv[1] >= 0) && body;
    layout->header_bytes = body ? (size_t)(body + 1 - text) : 0;
    need += count * per_item;
    if (result == GLINT_OK && need > body_bytes)
        result = status_fail(err, GLINT_ERR_INPUT,
                             "%s: the header declares elements that need at least %.0f bytes, but the file has %.0f "
                             "after its header (truncated, or a forged count)", path, need, body_bytes > 0 ? body_bytes : 0.0);
    free(text);
    return result;
}

glint_status ply_read_fast(const char *path, const ply_layout *l, model_warning_fn warn_fn, void *user, model_file *out,
                           glint_error *err, bool *taken) {
    model_file *m = out;
    size_t zero_area = 0;
    *taken = false;
    struct stat st;
    int problem;
    FILE *f = filepath_open_regular(path, &st, &problem);
    if (!f) return status_fail(err, GLINT_ERR_INPUT, "%s: cannot open: %s", path, filepath_problem_text(problem));
    size_t len;
    int errnum;
    unsigned char *data = (unsigned char *)file_read_stream(f, (size_t)st.st_size, MODEL_MAX_FILE_BYTES, &len, &errnum);
    fclose(f);
    if (!data)
        return errnum == ENOMEM ? fail_oom(path, err)
                                : status_fail(err, GLINT_ERR_INPUT, "%s: cannot read it: %s", path,
                                              errnum == EFBIG ? "larger than 1 GiB, the limit of a model's file" : strerror(errnum));
    size_t nv = l->vertices, nf = l->faces, at = l->header_bytes + nv * l->stride;
    glint_status result = GLINT_OK;
    if (at > len || nf * 13 > len - at) { // check_ply_header saw the sizes; a file may change between two opens
        free(data);
        return status_fail(err, GLINT_ERR_INPUT, "%s: the file ends before the elements its header declares", path);
    }
    // Every face a triangle (a count byte of 3), or assimp reads the file.
    for (size_t i = 0; i < nf; i++)
        if (data[at + 13 * i] != 3) {
            free(data);
            return GLINT_OK;
        }
    *taken = true;
    bool has_n = l->nrm[0] >= 0, has_uv = l->uv[0] >= 0;
    if (!(m->meshes = calloc(1, sizeof *m->meshes)) || !(m->materials = calloc(1, sizeof *m->materials)) ||
        !(m->placements = malloc(sizeof *m->placements)) || !(m->materials[0].name = strdup(""))) {
        free(data);
        return fail_oom(path, err);
    }
    m->mesh_count = m->material_count = m->placement_count = 1;
    m->placements[0] = (model_placement){0, mat4_identity()};
    model_material *mat = &m->materials[0];
    mat->is_default = true;
    mat->base_color = v3s(1.0f), mat->alpha = 1.0f, mat->metallic = mat->roughness = 1.0f, mat->ior = 1.5f;
    mat->base_color_image = mat->metallic_roughness_image = mat->normal_image = mat->emissive_image = -1;
    mat->transmission_image = -1, mat->normal_scale = 1.0f, mat->alpha_cutoff = 0.5f;
    mesh *g = &m->meshes[0].geometry;
    if ((nv && !(g->positions = malloc(nv * sizeof *g->positions))) || (nf && !(g->triangles = malloc(nf * sizeof *g->triangles))) ||
        (has_n && nv && !(g->normals = malloc(nv * sizeof *g->normals))) || (has_uv && nv && !(g->uvs = malloc(nv * sizeof *g->uvs))) ||
        (has_uv && nf && !(g->uv_corners = malloc(nf * sizeof *g->uv_corners)))) {
        free(data);
        return fail_oom(path, err);
    }
    for (size_t i = 0; i < nv && result == GLINT_OK; i++) {
        const unsigned char *v = data + l->header_bytes + i * l->stride;
        float p[3], n[3], t[2];
        for (int k = 0; k < 3; k++) memcpy(&p[k], v + l->pos[k], 4);
        g->positions[i] = v3(p[0], p[1], p[2]);
        if (!v3_is_finite(g->positions[i])) {
            result = status_fail(err, GLINT_ERR_INPUT,
                                 "%s: mesh 0, vertex %zu: the position (%g, %g, %g) is not finite; expected finite numbers",
                                 path, i, (double)p[0], (double)p[1], (double)p[2]);
            break;
        }
        if (has_n) {
            for (int k = 0; k < 3; k++) memcpy(&n[k], v + l->nrm[k], 4);
            g->normals[i] = v3(n[0], n[1], n[2]);
            if (!v3_is_finite(g->normals[i]))
                result = status_fail(err, GLINT_ERR_INPUT, "%s: mesh 0, vertex %zu: the normal is not finite", path, i);
        }
        if (has_uv) {
            for (int k = 0; k < 2; k++) memcpy(&t[k], v + l->uv[k], 4);
            g->uvs[i] = (uv2){t[0], t[1]};
            if (!(isfinite(t[0]) && isfinite(t[1])))
                result = status_fail(err, GLINT_ERR_INPUT, "%s: mesh 0, vertex %zu: the texture coordinate is not finite",
                                     path, i);
        }
    }
    g->position_count = nv;
    if (has_n) g->normal_count = nv, g->smooth = true, g->smooth_base = 0;
    if (has_uv) g->uv_count = nv;
    size_t tri = 0;
    for (size_t i = 0; i < nf && result == GLINT_OK; i++) {
        uint32_t ix[3];
        memcpy(ix, data + at + 13 * i + 1, 12);
        for (int k = 0; k < 3; k++)
            if (ix[k] >= nv) {
                // An int index below 0 reads as a large unsigned one, as assimp reads it: out of range either way.
                result = status_fail(err, GLINT_ERR_INPUT,
                                     "%s: mesh 0, face %zu: vertex index %u is out of range (the mesh has %zu vertices)",
                                     path, i, (unsigned)ix[k], nv);
                break;
            }
        if (result != GLINT_OK) break;
        int32_t a = (int32_t)ix[0], b = (int32_t)ix[1], c = (int32_t)ix[2];
        vec3 e = v3_cross(v3_sub(g->positions[b], g->positions[a]), v3_sub(g->positions[c], g->positions[a]));
        if (e.x == 0.0f && e.y == 0.0f && e.z == 0.0f) {
            zero_area++;
            continue;
        }
        g->triangles[tri] = (mesh_triangle){{a, b, c}, -1};
        if (has_uv) g->uv_corners[tri] = (mesh_corners){{a, b, c}};
        tri++;
    }
    free(data);
    g->triangle_count = tri;
    mesh_compute_bounds(g);
    if (result != GLINT_OK) return result;
    if (!model_file_add_input(m, &st, path)) return fail_oom(path, err);
    if (zero_area) warn(warn_fn, user, path, "%zu triangles of zero area (collinear or repeated corners): skipped", zero_area);
    if (tri == 0) warn(warn_fn, user, path, "the file places no triangles");
    return GLINT_OK;
}

