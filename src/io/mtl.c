// mtl.c — the MTL reader: each `newmtl` block read into a plain record (colours, scalars, illum, map_Kd), and the
// keys glint does not use noted for one warning per file; no glint material is made here (see mtl.h).
#include "io/mtl.h"
#include "core/array.h"
#include "core/filepath.h"
#include "core/strmap.h"
#include "io/decimal.h"
#include "io/obj_text.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

// What is read and not used, in the order the warning lists it (bit k of mtl_library.unsupported is entry k):
// the keys (the first UNSUPPORTED_STATEMENTS entries), then the options of used keys.
static const char *const unsupported_keys[] = {
    "Ka",      "Ps",     "Pc",    "Pcr",   "Pr",     "Pm",       "aniso",    "anisor",   "sharpness",
    "map_Ka",  "map_Ks", "map_Ns", "map_d", "map_Tr", "map_Ke",  "map_Pr",   "map_Pm",   "map_Ps",
    "map_aat", "bump",   "map_bump", "map_Bump", "norm", "disp", "decal", "refl", "map_refl",
    "map_Kd -options", "d -halo",
};
enum { UNSUPPORTED_STATEMENTS = 27, MAP_KD_OPTIONS = 27, D_HALO = 28 };
_Static_assert(sizeof unsupported_keys / sizeof unsupported_keys[0] == MTL_UNSUPPORTED_KEYS,
               "one name per bit of mtl_library.unsupported");
_Static_assert(MTL_UNSUPPORTED_KEYS <= 32, "the keys fit the bits of mtl_library.unsupported");

const char *mtl_unsupported_key_name(unsigned k) { return k < MTL_UNSUPPORTED_KEYS ? unsupported_keys[k] : NULL; }

/// The `newmtl` block being read.
typedef struct mtl_block {
    mtl_record rec;
    size_t name_len;
    bool duplicate; // the name was defined before: the block is read (and checked) but dropped
} mtl_block;

typedef struct mtl_parser {
    obj_reporter rep;
    const char *dir; // the MTL file's name: its first dir_len bytes are its directory
    size_t dir_len;
    bool skip_files;
    mtl_library *lib; // what is read so far: records, unsupported keys
    size_t cap;       // of lib->records
    strmap names;     // material name -> index in lib->records
    mtl_block cur;
    bool in_block;
} mtl_parser;

// Ends the current newmtl block: appends its record (a repeated name keeps the first definition).
static bool mtl_finish_block(mtl_parser *ps) {
    if (!ps->in_block) return true;
    ps->in_block = false;
    mtl_block *b = &ps->cur;
    mtl_library *lib = ps->lib;
    if (b->duplicate) {
        free(b->rec.name);
        free(b->rec.map_kd);
        return true;
    }
    if (lib->count >= OBJ_MAX_ELEMENTS ||
        !array_reserve((void **)&lib->records, &ps->cap, lib->count + 1, sizeof *lib->records)) {
        free(b->rec.name);
        free(b->rec.map_kd);
        return obj_out_of_memory(&ps->rep);
    }
    lib->records[lib->count] = b->rec;
    if (!strmap_put(&ps->names, b->rec.name, b->name_len, lib->count)) {
        free(b->rec.name);
        free(b->rec.map_kd);
        return obj_out_of_memory(&ps->rep);
    }
    lib->count++;
    return true;
}

// Notes entry k of unsupported_keys, given on the current line, for the library's warning.
static void note_unsupported(mtl_parser *ps, unsigned k) {
    mtl_library *lib = ps->lib;
    if (!lib->unsupported) lib->unsupported_line = ps->rep.line;
    lib->unsupported |= UINT32_C(1) << k;
}

// `Kd r [g b]` (g = b = r when only r is given); components must be finite and >= 0.
static bool mtl_color(mtl_parser *ps, obj_cursor *c, const char *kw, vec3 *out, bool *has) {
    obj_cursor peek = *c;
    const char *tok;
    size_t n;
    if (obj_next_token(&peek, &tok, &n) && (obj_token_is(tok, n, "spectral") || obj_token_is(tok, n, "xyz"))) {
        char what[32];
        snprintf(what, sizeof what, "%s %s", kw, obj_token_is(tok, n, "xyz") ? "xyz" : "spectral");
        obj_warn_unsupported(&ps->rep, what, strlen(what));
        return true;
    }
    float v[3];
    int count;
    if (!obj_parse_numbers(&ps->rep, c, v, 3, &count)) return false;
    if (count != 1 && count != 3) return obj_fail(&ps->rep, "'%s' has %d numbers, expected r g b", kw, count);
    if (count == 1) v[1] = v[2] = v[0];
    for (int i = 0; i < 3; i++)
        if (v[i] < 0.0f) return obj_fail(&ps->rep, "'%s' has a negative component %g, expected values >= 0", kw, (double)v[i]);
    *out = v3(v[0], v[1], v[2]);
    *has = true;
    return true;
}

// One number in [lo, hi].
static bool mtl_scalar(mtl_parser *ps, obj_cursor *c, const char *kw, float lo, float hi, float *out, bool *has) {
    float v[1];
    int count;
    if (!obj_parse_numbers(&ps->rep, c, v, 1, &count)) return false;
    if (count != 1) return obj_fail(&ps->rep, "'%s' has %d numbers, expected 1", kw, count);
    if (!(v[0] >= lo && v[0] <= hi)) {
        if (hi == INFINITY) return obj_fail(&ps->rep, "'%s' is %g, expected a value >= %g", kw, (double)v[0], (double)lo);
        return obj_fail(&ps->rep, "'%s' is %g, expected a value from %g to %g", kw, (double)v[0], (double)lo, (double)hi);
    }
    *out = v[0];
    *has = true;
    return true;
}

// `map_Kd [-options] file`: skips the options, resolves the file relative to the MTL's directory.
static bool mtl_map_kd(mtl_parser *ps, obj_cursor *c) {
    static const struct { const char *name; int args; } options[] = {
        {"-blendu", 1}, {"-blendv", 1}, {"-cc", 1}, {"-clamp", 1}, {"-bm", 1}, {"-boost", 1}, {"-texres", 1},
        {"-imfchan", 1}, {"-type", 1}, {"-mm", 2}, {"-o", -3}, {"-s", -3}, {"-t", -3},
    };
    for (;;) {
        obj_cursor peek = *c;
        const char *tok;
        size_t n;
        if (!obj_next_token(&peek, &tok, &n) || tok[0] != '-') break;
        int args = 0;
        for (size_t i = 0; i < sizeof options / sizeof options[0]; i++)
            if (obj_token_is(tok, n, options[i].name)) args = options[i].args;
        if (args == 0) break; // not an option: a file name that starts with '-'
        *c = peek;
        note_unsupported(ps, MAP_KD_OPTIONS);
        // -o, -s, -t take one to three numbers: take those that parse.
        for (int k = 0; k < (args < 0 ? -args : args); k++) {
            obj_cursor arg = *c;
            float f;
            if (!obj_next_token(&arg, &tok, &n)) break;
            if (args < 0 && k > 0 && decimal_parse_float(tok, n, &f) != DECIMAL_OK) break;
            *c = arg;
        }
    }
    const char *file;
    size_t n;
    obj_rest_of_line(c, &file, &n);
    if (n == 0) return obj_fail(&ps->rep, "'map_Kd' needs a file name");
    char *path = obj_join_path(ps->dir, ps->dir_len, file, n);
    if (!path) return obj_out_of_memory(&ps->rep);
    if (!ps->skip_files) {
        struct stat st;
        int e = filepath_problem(path, &st);
        if (e) {
            // Exporters on Windows write absolute paths: try the bare file name next to the MTL file.
            const char *slash = strrchr(path, '/');
            char *alt = slash ? obj_join_path(ps->dir, ps->dir_len, slash + 1, strlen(slash + 1)) : NULL;
            if (alt && filepath_problem(alt, &st) == 0) {
                free(path);
                path = alt;
            } else {
                free(alt);
                obj_warn_at(&ps->rep, ps->rep.line, "texture '%s' not found (%s); material '%s' uses its Kd colour",
                            obj_quote_path(file, n).s, filepath_problem_text(e),
                            obj_quote(ps->cur.rec.name, ps->cur.name_len).s);
                free(path);
                return true;
            }
        }
    }
    free(ps->cur.rec.map_kd);
    ps->cur.rec.map_kd = path;
    return true;
}

// Key k of unsupported_keys, read (Ka checked as a colour) and noted.
static bool mtl_unsupported(mtl_parser *ps, obj_cursor *c, unsigned k) {
    if (k == 0) { // Ka
        vec3 ka;
        bool has = false;
        if (!mtl_color(ps, c, "Ka", &ka, &has)) return false;
        if (!has) return true; // `Ka spectral`: a warning of its own
    }
    note_unsupported(ps, k);
    return true;
}

// `newmtl name`: ends the block before it and starts one.
static bool mtl_newmtl(mtl_parser *ps, obj_cursor *c) {
    if (!mtl_finish_block(ps)) return false;
    const char *name;
    size_t n;
    obj_rest_of_line(c, &name, &n);
    if (n == 0) return obj_fail(&ps->rep, "'newmtl' needs a material name");
    memset(&ps->cur, 0, sizeof ps->cur);
    ps->cur.rec.name = obj_strdup_n(name, n);
    if (!ps->cur.rec.name) return obj_out_of_memory(&ps->rep);
    ps->cur.name_len = n;
    ps->cur.rec.line = ps->rep.line;
    ps->cur.rec.values.illum = -1;
    ps->in_block = true;
    if (strmap_get(&ps->names, name, n, NULL)) {
        ps->cur.duplicate = true;
        obj_warn_at(&ps->rep, ps->rep.line, "material '%s' is defined again; the first definition is used",
                    obj_quote(name, n).s);
    }
    return true;
}

static bool mtl_statement(mtl_parser *ps, obj_cursor *c) {
    const char *kw;
    size_t kn;
    if (!obj_next_token(c, &kw, &kn)) return true;
    if (obj_token_is(kw, kn, "newmtl")) return mtl_newmtl(ps, c);
    static const char *const used[] = {"Kd", "Ks", "Ke", "Tf", "Ns", "Ni", "d", "Tr", "illum", "map_Kd"};
    bool is_used = false;
    for (size_t i = 0; i < sizeof used / sizeof used[0] && !is_used; i++) is_used = obj_token_is(kw, kn, used[i]);
    unsigned unsupported = UNSUPPORTED_STATEMENTS;
    for (unsigned k = 0; k < UNSUPPORTED_STATEMENTS && !is_used && unsupported == UNSUPPORTED_STATEMENTS; k++)
        if (obj_token_is(kw, kn, unsupported_keys[k])) unsupported = k;
    if (!is_used && unsupported == UNSUPPORTED_STATEMENTS) {
        obj_warn_unsupported(&ps->rep, kw, kn);
        return true;
    }
    if (!ps->in_block) return obj_fail(&ps->rep, "'%s' before any 'newmtl', expected 'newmtl name' first", obj_quote(kw, kn).s);
    if (!is_used) return mtl_unsupported(ps, c, unsupported);
    mtl_values *b = &ps->cur.rec.values;
    if (obj_token_is(kw, kn, "Kd")) return mtl_color(ps, c, "Kd", &b->kd, &b->has_kd);
    if (obj_token_is(kw, kn, "Ks")) return mtl_color(ps, c, "Ks", &b->ks, &b->has_ks);
    if (obj_token_is(kw, kn, "Ke")) return mtl_color(ps, c, "Ke", &b->ke, &b->has_ke);
    if (obj_token_is(kw, kn, "Tf")) return mtl_color(ps, c, "Tf", &b->tf, &b->has_tf);
    if (obj_token_is(kw, kn, "Ns")) return mtl_scalar(ps, c, "Ns", 0.0f, INFINITY, &b->ns, &b->has_ns);
    if (obj_token_is(kw, kn, "Ni")) return mtl_scalar(ps, c, "Ni", 0.0f, INFINITY, &b->ni, &b->has_ni);
    if (obj_token_is(kw, kn, "Tr")) return mtl_scalar(ps, c, "Tr", 0.0f, 1.0f, &b->tr, &b->has_tr);
    if (obj_token_is(kw, kn, "d")) {
        obj_cursor peek = *c;
        const char *tok;
        size_t n;
        if (obj_next_token(&peek, &tok, &n) && obj_token_is(tok, n, "-halo")) {
            *c = peek;
            note_unsupported(ps, D_HALO);
        }
        return mtl_scalar(ps, c, "d", 0.0f, 1.0f, &b->d, &b->has_d);
    }
    if (obj_token_is(kw, kn, "illum")) {
        const char *tok;
        size_t n;
        int64_t v;
        if (!obj_next_token(c, &tok, &n)) return obj_fail(&ps->rep, "'illum' needs an illumination model, expected an integer from 0 to 10");
        if (!obj_parse_index(tok, n, &v) || v < 0 || v > 10)
            return obj_fail(&ps->rep, "'illum' is '%s', expected an integer from 0 to 10", obj_quote(tok, n).s);
        if (obj_next_token(c, &tok, &n)) return obj_fail(&ps->rep, "'illum' has more than one value, expected an integer from 0 to 10");
        b->illum = (int)v;
        return true;
    }
    return mtl_map_kd(ps, c);
}

static bool mtl_line(void *state, obj_cursor *c) { return mtl_statement(state, c); }

void mtl_library_free(mtl_library *lib) {
    for (size_t i = 0; i < lib->count; i++) {
        free(lib->records[i].name);
        free(lib->records[i].map_kd);
    }
    free(lib->records);
    memset(lib, 0, sizeof *lib);
}

glint_status mtl_parse(const char *name, const char *text, size_t length, const mtl_options *opt, mtl_library *out,
                       glint_error *err) {
    memset(out, 0, sizeof *out);
    mtl_parser ps;
    memset(&ps, 0, sizeof ps);
    ps.rep.name = name;
    ps.rep.warn = opt ? opt->warn : NULL;
    ps.rep.user = opt ? opt->user : NULL;
    ps.rep.err = err;
    ps.rep.warnings = &out->warning_count;
    ps.dir = name;
    ps.dir_len = filepath_dir_length(name);
    ps.skip_files = opt && opt->skip_files;
    ps.lib = out;
    bool ok = obj_for_each_line(text, length, &ps.rep, mtl_line, &ps) && mtl_finish_block(&ps);
    if (ps.in_block) { // a failure inside a block
        free(ps.cur.rec.name);
        free(ps.cur.rec.map_kd);
    }
    strmap_free(&ps.names);
    if (!ok) {
        mtl_library_free(out);
        return ps.rep.nomem ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}
