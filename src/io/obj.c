// obj.c — the OBJ reader's entry points: a file or a text read from its first line to its last (lines by
// obj_fast.c, which hands the rest to obj_statements.c), its materials given their definitions at the end, and
// the model freed.
#include "io/obj.h"
#include "core/filepath.h"
#include "core/strmap.h"
#include "io/mtl.h"
#include "io/obj_parser.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Frees records and their strings.
static void free_records(mtl_record *r, size_t count) {
    for (size_t i = 0; i < count; i++) {
        free(r[i].name);
        free(r[i].map_kd);
    }
    free(r);
}

void obj_model_free(obj_model *m) {
    mesh_free(&m->mesh);
    for (size_t i = 0; i < m->material_count; i++) {
        free(m->materials[i].name);
        free(m->materials[i].diffuse_map);
    }
    free(m->materials);
    for (size_t i = 0; i < m->library_count; i++) free(m->libraries[i].path);
    free(m->libraries);
    memset(m, 0, sizeof *m);
    m->mesh.bounds = bounds3_empty();
}

// Readies the parser for the first line of file `name`.
static void obj_begin(obj_parser *ps, const char *name, const obj_options *opt, obj_model *out, glint_error *err) {
    memset(out, 0, sizeof *out);
    out->mesh.bounds = bounds3_empty();
    memset(ps, 0, sizeof *ps);
    ps->rep.name = name;
    ps->rep.warn = opt ? opt->warn : NULL;
    ps->rep.user = opt ? opt->user : NULL;
    ps->rep.err = err;
    ps->rep.warnings = &out->warning_count;
    ps->model = out;
    ps->opt = opt;
    ps->material = -1;
    ps->dir = name;
    ps->dir_len = filepath_dir_length(name);
}

// After the last line (ok) or a failure (!ok): gives the materials their definitions, says what is left to
// say, frees the parser's scratch, and on failure the model too.
static glint_status obj_end(obj_parser *ps, bool ok) {
    obj_model *out = ps->model;
    if (ok) ok = obj_resolve_materials(ps);
    if (ok) {
        if (out->zero_area_faces > 1)
            obj_warn_at(&ps->rep, 0, "%zu zero-area faces skipped in total (the first on line %ld)",
                        out->zero_area_faces, ps->first_zero_line);
        if (out->mesh.triangle_count == 0) obj_warn_at(&ps->rep, 0, "no faces; the mesh is empty");
    }
    free(ps->corners);
    free(ps->px);
    free(ps->py);
    free(ps->next);
    free(ps->prev);
    strmap_free(&ps->slots);
    strmap_free(&ps->def_names);
    free_records(ps->defs, ps->def_count);
    // The model keeps the list of libraries read: they are inputs of the scene as much as the OBJ file.
    out->libraries = ps->libs;
    out->library_count = ps->lib_count;
    if (!ok) {
        obj_model_free(out);
        return ps->rep.nomem ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

glint_status obj_parse(const char *name, const char *text, size_t length, const obj_options *opt, obj_model *out,
                       glint_error *err) {
    obj_parser ps;
    obj_begin(&ps, name, opt, out, err);
    return obj_end(&ps, obj_lines(&ps, text, length));
}

// The message of a file that cannot be read.
static glint_status obj_file_failure(const char *path, int e, glint_error *err) {
    glint_status st = e == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    if (!err) return st;
    if (e == ENOMEM) snprintf(err->message, sizeof err->message, "%s: out of memory reading the file", path);
    else if (e == EFBIG)
        snprintf(err->message, sizeof err->message, "%s: the OBJ file is larger than %zu bytes (%zu GiB)", path,
                 (size_t)OBJ_MAX_FILE_BYTES, (size_t)OBJ_MAX_FILE_BYTES >> 30);
    else snprintf(err->message, sizeof err->message, "%s: cannot open: %s", path, filepath_problem_text(e));
    return st;
}

glint_status obj_load(const char *path, const obj_options *opt, obj_model *out, glint_error *err) {
    memset(out, 0, sizeof *out);
    out->mesh.bounds = bounds3_empty();
    size_t size;
    int e;
    FILE *f = obj_open_file(path, OBJ_MAX_FILE_BYTES, &size, &e);
    if (!f) return obj_file_failure(path, e, err);
    obj_parser ps;
    obj_begin(&ps, path, opt, out, err);
    bool ok = obj_read_open_file(&ps, f, size, &e);
    fclose(f);
    glint_status st = obj_end(&ps, ok);
    return ok || !e ? st : obj_file_failure(path, e, err);
}
