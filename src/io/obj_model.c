// obj_model.c — the OBJ model as it is built: positions, normals and texture coordinates stored (the last step of
// both the statements and the fast paths), material slots opened by `usemtl` and given their definitions at the end.
#include "core/array.h"
#include "core/strmap.h"
#include "io/obj_parser.h"

#include <string.h>

// ---------------------------------------------------------------------------------------------------------
// Elements

bool obj_too_many(obj_reporter *r, const char *what) {
    return obj_fail(r, "too many %s, expected at most %d", what, OBJ_MAX_ELEMENTS);
}

bool obj_add_position(obj_parser *ps, const float *v) {
    mesh *m = &ps->model->mesh;
    if (m->position_count >= OBJ_MAX_ELEMENTS) return obj_too_many(&ps->rep, "vertices");
    if (m->position_count == ps->pos_cap &&
        !array_reserve((void **)&m->positions, &ps->pos_cap, m->position_count + 1, sizeof *m->positions))
        return obj_out_of_memory(&ps->rep);
    m->positions[m->position_count++] = v3(v[0], v[1], v[2]);
    return true;
}

bool obj_add_normal(obj_parser *ps, const float *v) {
    mesh *m = &ps->model->mesh;
    if (m->normal_count >= OBJ_MAX_ELEMENTS) return obj_too_many(&ps->rep, "normals");
    if (m->normal_count == ps->nrm_cap &&
        !array_reserve((void **)&m->normals, &ps->nrm_cap, m->normal_count + 1, sizeof *m->normals))
        return obj_out_of_memory(&ps->rep);
    m->normals[m->normal_count++] = v3(v[0], v[1], v[2]);
    return true;
}

bool obj_add_texcoord(obj_parser *ps, const float *v, int count) {
    mesh *m = &ps->model->mesh;
    if (m->uv_count >= OBJ_MAX_ELEMENTS) return obj_too_many(&ps->rep, "texture coordinates");
    if (m->uv_count == ps->uv_cap && !array_reserve((void **)&m->uvs, &ps->uv_cap, m->uv_count + 1, sizeof *m->uvs))
        return obj_out_of_memory(&ps->rep);
    m->uvs[m->uv_count++] = (uv2){v[0], count > 1 ? v[1] : 0.0f};
    return true;
}

// ---------------------------------------------------------------------------------------------------------
// Material slots

bool obj_use_material(obj_parser *ps, const char *name, size_t n) {
    size_t found;
    int32_t slot = strmap_get(&ps->slots, name, n, &found) ? (int32_t)found : -1;
    if (slot < 0) {
        obj_model *mo = ps->model;
        if (mo->material_count >= OBJ_MAX_ELEMENTS) return obj_too_many(&ps->rep, "materials");
        if (!array_reserve((void **)&mo->materials, &ps->slot_cap, mo->material_count + 1, sizeof *mo->materials))
            return obj_out_of_memory(&ps->rep);
        obj_material *m = &mo->materials[mo->material_count];
        memset(m, 0, sizeof *m);
        m->name = obj_strdup_n(name, n);
        if (!m->name) return obj_out_of_memory(&ps->rep);
        m->mtl.illum = -1;
        m->line = ps->rep.line;
        slot = (int32_t)mo->material_count++;
        if (!strmap_put(&ps->slots, m->name, n, (size_t)slot)) return obj_out_of_memory(&ps->rep);
    }
    ps->material = slot;
    return true;
}

bool obj_resolve_materials(obj_parser *ps) {
    obj_model *mo = ps->model;
    for (size_t i = 0; i < mo->material_count; i++) {
        obj_material *slot = &mo->materials[i];
        size_t d;
        if (!strmap_get(&ps->def_names, slot->name, strlen(slot->name), &d)) {
            obj_warn_at(&ps->rep, slot->line, "material '%s' is not defined in any material library; using the default material",
                        obj_quote(slot->name, strlen(slot->name)).s);
            continue;
        }
        const mtl_record *def = &ps->defs[d];
        slot->defined = true;
        slot->mtl = def->values;
        if (def->map_kd && !(slot->diffuse_map = obj_strdup_n(def->map_kd, strlen(def->map_kd))))
            return obj_out_of_memory(&ps->rep);
    }
    return true;
}
