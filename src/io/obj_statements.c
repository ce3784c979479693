// obj_statements.c — the OBJ reader's statements: every line as the format allows it (v, vn, vt, f in every corner
// form, usemtl, mtllib, o, g, s), with every message. The fast paths (obj_fast.c) hand here the lines they do not
// take; faces go to obj_polygon.c, what is read to obj_model.c.
#include "core/array.h"
#include "core/filepath.h"
#include "core/strmap.h"
#include "io/mtl.h"
#include "io/obj_parser.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

// ---------------------------------------------------------------------------------------------------------
// Elements

static bool obj_vertex(obj_parser *ps, obj_cursor *c) {
    float v[7];
    int count;
    if (!obj_parse_numbers(&ps->rep, c, v, 7, &count)) return false;
    if (count < 3 || count > 7) return obj_fail(&ps->rep, "'v' has %d numbers, expected 3 (x y z) to 7", count);
    return obj_add_position(ps, v);
}

static bool obj_normal(obj_parser *ps, obj_cursor *c) {
    float v[3];
    int count;
    if (!obj_parse_numbers(&ps->rep, c, v, 3, &count)) return false;
    if (count != 3) return obj_fail(&ps->rep, "'vn' has %d numbers, expected 3 (x y z)", count);
    return obj_add_normal(ps, v);
}

static bool obj_texcoord(obj_parser *ps, obj_cursor *c) {
    float v[3] = {0, 0, 0};
    int count;
    if (!obj_parse_numbers(&ps->rep, c, v, 3, &count)) return false;
    if (count < 1 || count > 3) return obj_fail(&ps->rep, "'vt' has %d numbers, expected 1 to 3 (u [v [w]])", count);
    return obj_add_texcoord(ps, v, count);
}

// A 1-based or negative (relative) index into `count` elements -> 0-based.
static bool resolve_index(obj_parser *ps, const char *tok, size_t n, int64_t idx, size_t count, const char *what,
                          const char *plural, int32_t *out) {
    if (idx > 0 && (uint64_t)idx <= count) {
        *out = (int32_t)(idx - 1);
        return true;
    }
    if (idx < 0 && (uint64_t)(-idx) <= count) {
        *out = (int32_t)((int64_t)count + idx);
        return true;
    }
    obj_quoted q = obj_quote(tok, n);
    if (count == 0) return obj_fail(&ps->rep, "%s index %s out of range, no %s defined before this face", what, q.s, plural);
    return obj_fail(&ps->rep, "%s index %s out of range, expected 1..%zu or -%zu..-1", what, q.s, count, count);
}

// One face corner: v, v/vt, v//vn or v/vt/vn.
static bool parse_corner(obj_parser *ps, const char *tok, size_t n, obj_corner *out) {
    const mesh *m = &ps->model->mesh;
    const char *s1 = memchr(tok, '/', n);
    const char *s2 = s1 ? memchr(s1 + 1, '/', (size_t)(tok + n - s1 - 1)) : NULL;
    const char *vs = tok, *ts = NULL, *ns = NULL;
    size_t vl = s1 ? (size_t)(s1 - tok) : n, tl = 0, nl = 0;
    bool ok = true;
    if (s1 && !s2) {
        ts = s1 + 1;
        tl = (size_t)(tok + n - ts);
        ok = tl > 0;
    } else if (s2) {
        ts = s1 + 1;
        tl = (size_t)(s2 - ts);
        ns = s2 + 1;
        nl = (size_t)(tok + n - ns);
        ok = nl > 0 && !memchr(ns, '/', nl);
    }
    int64_t vi = 0, ti = 0, ni = 0;
    ok = ok && obj_parse_index(vs, vl, &vi) && (tl == 0 || obj_parse_index(ts, tl, &ti)) && (nl == 0 || obj_parse_index(ns, nl, &ni));
    if (!ok)
        return obj_fail(&ps->rep, "malformed face vertex '%s', expected v, v/vt, v//vn or v/vt/vn with integer indices",
                        obj_quote(tok, n).s);
    out->t = out->n = -1;
    if (!resolve_index(ps, vs, vl, vi, m->position_count, "vertex", "vertices", &out->v)) return false;
    if (tl && !resolve_index(ps, ts, tl, ti, m->uv_count, "texture coordinate", "texture coordinates", &out->t))
        return false;
    if (nl && !resolve_index(ps, ns, nl, ni, m->normal_count, "normal", "normals", &out->n)) return false;
    return true;
}

static bool obj_face(obj_parser *ps, obj_cursor *c) {
    const char *tok;
    size_t len, n = 0;
    while (obj_next_token(c, &tok, &len)) {
        if (n == OBJ_MAX_FACE_CORNERS)
            return obj_fail(&ps->rep, "face has more than %d vertices, expected at most %d", OBJ_MAX_FACE_CORNERS,
                            OBJ_MAX_FACE_CORNERS);
        if (!array_reserve((void **)&ps->corners, &ps->corner_cap, n + 1, sizeof *ps->corners))
            return obj_out_of_memory(&ps->rep);
        if (!parse_corner(ps, tok, len, &ps->corners[n])) return false;
        n++;
    }
    if (n < 3) return obj_fail(&ps->rep, "face has %zu vertices, expected at least 3", n);
    return obj_triangulate(ps, n);
}

// ---------------------------------------------------------------------------------------------------------
// Materials

static bool obj_usemtl(obj_parser *ps, obj_cursor *c) {
    const char *name;
    size_t n;
    obj_rest_of_line(c, &name, &n);
    if (n == 0) return obj_fail(&ps->rep, "'usemtl' needs a material name");
    return obj_use_material(ps, name, n);
}

// Reads one material library (once) and appends its definitions; a missing file is a warning.
static bool read_library(obj_parser *ps, const char *path, const char *shown, size_t shown_len) {
    for (size_t i = 0; i < ps->lib_count; i++)
        if (strcmp(ps->libs[i].path, path) == 0) return true;
    size_t len;
    int e;
    char *text = obj_read_file(path, MTL_MAX_FILE_BYTES, &len, &e);
    if (!text) {
        obj_quoted q = obj_quote_path(shown, shown_len);
        if (e == ENOMEM) {
            ps->rep.nomem = true;
            return obj_fail(&ps->rep, "out of memory reading material library '%s'", q.s);
        }
        if (e == EFBIG)
            return obj_fail(&ps->rep, "material library '%s' is larger than %zu bytes (%zu MiB)", q.s,
                            (size_t)MTL_MAX_FILE_BYTES, (size_t)MTL_MAX_FILE_BYTES >> 20);
        obj_warn_at(&ps->rep, ps->rep.line, "cannot open material library '%s' (%s); its materials are undefined", q.s,
                    filepath_problem_text(e));
        return true;
    }
    char *copy = obj_strdup_n(path, strlen(path));
    if (!copy || !array_reserve((void **)&ps->libs, &ps->lib_cap, ps->lib_count + 1, sizeof *ps->libs)) {
        free(copy);
        free(text);
        return obj_out_of_memory(&ps->rep);
    }
    obj_library *entry = &ps->libs[ps->lib_count++];
    *entry = (obj_library){copy, 0, 0};
    mtl_library lib;
    mtl_options mopt = {ps->rep.warn, ps->rep.user, ps->opt && ps->opt->skip_files};
    glint_status status = mtl_parse(path, text, len, &mopt, &lib, ps->rep.err);
    free(text);
    ps->model->warning_count += lib.warning_count;
    if (status != GLINT_OK) {
        ps->rep.nomem = status == GLINT_ERR_RENDER;
        return false;
    }
    entry->unsupported = lib.unsupported;
    entry->unsupported_line = lib.unsupported_line;
    bool ok = true;
    for (size_t i = 0; i < lib.count; i++) {
        mtl_record *d = &lib.records[i];
        size_t nl = strlen(d->name);
        // A name that an earlier library defined keeps that first definition.
        bool keep = ok && !strmap_get(&ps->def_names, d->name, nl, NULL);
        if (keep && (ps->def_count >= OBJ_MAX_ELEMENTS ||
                     !array_reserve((void **)&ps->defs, &ps->def_cap, ps->def_count + 1, sizeof *ps->defs) ||
                     !strmap_put(&ps->def_names, d->name, nl, ps->def_count)))
            keep = ok = obj_out_of_memory(&ps->rep);
        if (keep) {
            ps->defs[ps->def_count++] = *d; // the strings now belong to ps->defs
            *d = (mtl_record){0};
        }
    }
    mtl_library_free(&lib);
    return ok;
}

static bool obj_mtllib(obj_parser *ps, obj_cursor *c) {
    const char *names;
    size_t n;
    obj_rest_of_line(c, &names, &n);
    if (n == 0) return obj_fail(&ps->rep, "'mtllib' needs a file name");
    if (ps->opt && ps->opt->skip_files) return true;
    char *whole = obj_join_path(ps->dir, ps->dir_len, names, n);
    if (!whole) return obj_out_of_memory(&ps->rep);
    // The whole argument may be one name with blanks; otherwise it is a list of names.
    struct stat st;
    bool single = filepath_problem(whole, &st) == 0 || (!memchr(names, ' ', n) && !memchr(names, '\t', n));
    if (single) {
        bool ok = read_library(ps, whole, names, n);
        free(whole);
        return ok;
    }
    free(whole);
    obj_cursor list = {names, names + n};
    const char *tok;
    size_t len;
    while (obj_next_token(&list, &tok, &len)) {
        char *path = obj_join_path(ps->dir, ps->dir_len, tok, len);
        if (!path) return obj_out_of_memory(&ps->rep);
        bool ok = read_library(ps, path, tok, len);
        free(path);
        if (!ok) return false;
    }
    return true;
}

bool obj_statement(obj_parser *ps, obj_cursor *c) {
    const char *kw;
    size_t n;
    if (!obj_next_token(c, &kw, &n)) return true;
    if (n == 1) {
        switch (kw[0]) {
        case 'v': return obj_vertex(ps, c);
        case 'f': return obj_face(ps, c);
        case 'o': case 'g': case 's': return true; // objects, groups and smoothing groups carry nothing we need
        default: break;
        }
    } else if (n == 2 && kw[0] == 'v') {
        if (kw[1] == 'n') return obj_normal(ps, c);
        if (kw[1] == 't') return obj_texcoord(ps, c);
    } else if (obj_token_is(kw, n, "usemtl")) {
        return obj_usemtl(ps, c);
    } else if (obj_token_is(kw, n, "mtllib")) {
        return obj_mtllib(ps, c);
    }
    obj_warn_unsupported(&ps->rep, kw, n);
    return true;
}
