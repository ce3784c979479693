// scene_file_common.c — what every section of the scene reader shares: failure and warning messages, lookups in the
// material and texture name tables, files the scene refers to (paths relative to the scene file), and the extent
// within which everything renders. It calls no other scene_file*.c file.
#include "scene/scene_file_common.h"
#include "core/filepath.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---------------------------------------------------------------------------------------------
// Messages

bool sf_fail_oom(sf_loader *ld) {
    snprintf(ld->r.err->message, sizeof ld->r.err->message, "%s: out of memory while reading the scene", ld->r.name);
    ld->r.status = GLINT_ERR_RENDER;
    return false;
}

// ---------------------------------------------------------------------------------------------
// Warnings: collected in the scene (the library prints nothing); the command line shows them

void sf_add_warning(sf_loader *ld, const char *message) {
    if (ld->scene->warning_count >= SF_MAX_WARNINGS) {
        ld->warnings_dropped++;
        return;
    }
    if (!scene_add_warning(ld->scene, message)) ld->warning_oom = true;
}

void sf_warn_at(sf_loader *ld, size_t offset, const char *fmt, ...) {
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    jr_vformat(&ld->r, msg, sizeof msg, offset, "warning: ", fmt, ap);
    va_end(ap);
    sf_add_warning(ld, msg);
}

// ---------------------------------------------------------------------------------------------
// The material and texture name tables: lookups (scene_file.c fills them as it reads the collections)

const sf_name *sf_names_find(const sf_names *t, const char *name) {
    size_t i;
    return strmap_get(&t->map, name, strlen(name), &i) ? &t->list[i] : NULL;
}

/// "material "blu" is not defined (defined: red, green)": lists the first few names in definition order.
bool sf_fail_undefined(sf_loader *ld, jr_val v, const sf_names *map, const char *kind) {
    char names[512], got[96];
    size_t n = 0, listed = 0;
    names[0] = '\0';
    for (size_t i = 0; i < map->count && listed < SF_LIST_NAMES; i++) {
        int w = snprintf(names + n, sizeof names - n, "%s%s", listed ? ", " : "", map->list[i].name);
        if (w < 0 || (size_t)w >= sizeof names - n) break;
        n += (size_t)w;
        listed++;
    }
    const char *what = jr_describe(&ld->r, v, got, sizeof got);
    const char *plural = kind[strlen(kind) - 1] == 'h' ? "es" : "s"; // meshes
    if (map->count == 0)
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "%s %s is not defined (no named %s%s are defined)", kind,
                          what, kind, plural);
    if (listed < map->count)
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "%s %s is not defined (defined: %s and %zu more)", kind, what, names,
                          map->count - listed);
    return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "%s %s is not defined (defined: %s)", kind, what, names);
}

// ---------------------------------------------------------------------------------------------
// Files the scene refers to (meshes, images): paths relative to the scene file's directory

/// `file` as a path usable from the current directory: absolute paths as they are, others joined to the
/// scene file's directory. NULL when out of memory.
static char *resolve_path(const sf_loader *ld, const char *file) {
    return filepath_join(ld->base, filepath_dir_length(ld->base), file, strlen(file));
}

// " (resolved/path)" when the path opened differs from the one written, else "".
const char *sf_resolved_note(const char *written, const char *path, char *buf, size_t size) {
    if (strcmp(written, path) == 0) return "";
    char tail[404];
    snprintf(buf, size, " (%s)", filepath_tail(path, 400, tail, sizeof tail));
    return buf;
}

/// Reads the required path `key` of o, resolves it (*path, malloc'd) and checks that it names a regular
/// file (*id). `kind` ("mesh", "image") names the file in messages: `image file "a.png": cannot open: reason`.
bool sf_read_file_path(sf_loader *ld, const jr_obj *o, const char *key, const char *kind, char **path, sf_file_id *id,
                           jr_val *where) {
    const jr_member *m;
    char got[96], note[420];
    *path = NULL;
    if (!jr_lookup(&ld->r, o, key, true, &m)) return false;
    jr_val v = *where = m->val;
    if (!cJSON_IsString(v.item) || v.item->valuestring[0] == '\0')
        return jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok),
                          "\"%s\" must be a non-empty string (a path relative to the scene file), got %s", key,
                          jr_describe(&ld->r, v, got, sizeof got));
    const char *written = v.item->valuestring;
    char *p = resolve_path(ld, written);
    if (!p) return sf_fail_oom(ld);
    struct stat st;
    int e = filepath_problem(p, &st);
    if (e != 0) {
        jr_fail_at(&ld->r, jr_offset(&ld->r, v.tok), "%s file %s%s: cannot open: %s", kind, jr_describe_path(&ld->r, v, got, sizeof got),
                   sf_resolved_note(written, p, note, sizeof note), filepath_problem_text(e));
        free(p);
        return false;
    }
    if (!scene_add_input(ld->scene, (uint64_t)st.st_dev, (uint64_t)st.st_ino, p)) {
        free(p);
        return sf_fail_oom(ld);
    }
    *path = p;
    *id = (sf_file_id){st.st_dev, st.st_ino};
    return true;
}

// ---------------------------------------------------------------------------------------------
// The extent

bool sf_check_extent(sf_loader *ld, size_t offset, const char *what, bounds3 b) {
    for (int k = 0; k < 3; k++) {
        float lo = v3_comp(b.lo, k), hi = v3_comp(b.hi, k), far = fabsf(lo) > fabsf(hi) ? lo : hi;
        if (fabsf(lo) <= (float)SF_MAX_EXTENT && fabsf(hi) <= (float)SF_MAX_EXTENT) continue;
        return jr_fail_at(&ld->r, offset,
                          "%s reaches %g on the %c axis; glint renders within [-1e9, 1e9] on every axis (beyond, "
                          "squared distances overflow single precision and samples would be NaN)",
                          what, (double)far, "xyz"[k]);
    }
    return true;
}

// The shared grey Lambertian of faces that have no material of their own.
bool sf_fallback_material(sf_loader *ld, uint32_t *index) {
    if (ld->fallback_material < 0) {
        material m = material_default(MAT_LAMBERTIAN);
        if ((ld->fallback_material = scene_add_material(ld->scene, &m, NULL)) < 0) return sf_fail_oom(ld);
    }
    *index = (uint32_t)ld->fallback_material;
    return true;
}

bool sf_add_file_material(sf_loader *ld, size_t where, const char *file, const char *name, const material *m,
                          uint32_t *index) {
    if (ld->scene->material_count >= SF_MAX_ITEMS)
        return jr_fail_at(&ld->r, where, "too many materials (the limit is %d)", SF_MAX_ITEMS);
    size_t n = strlen(file) + strlen(name) + 2;
    char *full = malloc(n);
    if (!full) return sf_fail_oom(ld);
    snprintf(full, n, "%s:%s", file, name);
    long k = scene_add_material(ld->scene, m, full);
    free(full);
    if (k < 0) return sf_fail_oom(ld);
    *index = (uint32_t)k;
    return true;
}
