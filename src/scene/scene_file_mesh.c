// scene_file_mesh.c — "mesh" objects: an OBJ file is loaded once (io/obj), its MTL materials become scene
// materials by the MTL -> glint policy below ("file:name", map_Kd as an image texture, a grey fallback for faces
// without one; the MTL keys it does not use named in one warning per file), and every object that names the file
// places an instance of it.
#include "scene/scene_file_common.h"
#include "core/array.h"
#include "core/filepath.h"
#include "core/trace.h"
#include "io/obj.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

// ---------------------------------------------------------------------------------------------
// MTL materials -> glint materials

static float max3(vec3 v) { return fmaxf(v.x, fmaxf(v.y, v.z)); }
static float clamp01(float x) { return fminf(1.0f, fmaxf(0.0f, x)); }
static vec3 clamp01v(vec3 v) { return v3(clamp01(v.x), clamp01(v.y), clamp01(v.z)); }

// The first rule that applies (docs/scene-format.md lists them with every MTL key):
//   1. Ke with a component > 0                             -> diffuse_light, emission Ke
//   2. transparent: d < 1, or (without d) Tr > 0, or illum 4, 6, 7 or 9
//                                                          -> dielectric, ior Ni (1.5 when absent or <= 0),
//                                                             tint Tf clamped to [0,1] (white when absent)
//   3. illum 3, 5 or 8 with strong Ks: max(Ks) >= 0.25 and max(Ks) >= max(Kd)
//                                                          -> metal, albedo Ks clamped to [0,1],
//                                                             fuzz sqrt(2 / (Ns + 2)) clamped to [0,1] (0 without Ns)
//   4. otherwise                                           -> lambertian, albedo Kd (0.5 grey when absent)
// map_Kd replaces the albedo of a Lambertian (map_obj_materials).
material sf_mtl_material(const mtl_values *b) {
    if (b->has_ke && max3(b->ke) > 0.0f) {
        material m = material_default(MAT_DIFFUSE_LIGHT);
        m.emission = b->ke;
        return m;
    }
    bool transparent = b->has_d ? b->d < 1.0f : (b->has_tr && b->tr > 0.0f);
    if (b->illum == 4 || b->illum == 6 || b->illum == 7 || b->illum == 9) transparent = true;
    if (transparent) {
        material m = material_default(MAT_DIELECTRIC);
        if (b->has_ni && b->ni > 0.0f) m.ior = b->ni;
        if (b->has_tf) m.albedo = clamp01v(b->tf);
        return m;
    }
    vec3 kd = b->has_kd ? b->kd : v3s(0.5f);
    if ((b->illum == 3 || b->illum == 5 || b->illum == 8) && b->has_ks && max3(b->ks) >= 0.25f &&
        max3(b->ks) >= max3(kd)) {
        material m = material_default(MAT_METAL);
        m.albedo = clamp01v(b->ks);
        // A Phong exponent n corresponds to a Beckmann roughness of about sqrt(2 / (n + 2)).
        m.fuzz = b->has_ns ? clamp01(sqrtf(2.0f / (b->ns + 2.0f))) : 0.0f;
        return m;
    }
    material m = material_default(MAT_LAMBERTIAN);
    m.albedo = kd;
    return m;
}

// Keeps "LIBRARY:LINE: warning: MTL keys not supported: Ka, bump; ignored (reported once per file)".
static void warn_unsupported_keys(sf_loader *ld, const obj_library *lib) {
    char keys[512];
    size_t k = 0;
    keys[0] = '\0';
    for (unsigned i = 0; i < MTL_UNSUPPORTED_KEYS; i++)
        if (lib->unsupported & (UINT32_C(1) << i)) {
            int w = snprintf(keys + k, sizeof keys - k, "%s%s", k ? ", " : "", mtl_unsupported_key_name(i));
            if (w > 0 && (size_t)w < sizeof keys - k) k += (size_t)w;
        }
    char msg[2600];
    snprintf(msg, sizeof msg, "%.2000s:%ld: warning: MTL keys not supported: %s; ignored in every material (reported "
             "once per file)", lib->path, lib->unsupported_line, keys);
    sf_add_warning(ld, msg);
}

// ---------------------------------------------------------------------------------------------
// Meshes from OBJ files

// The OBJ reader's callback.
static void collect_warning(const char *message, void *user) { sf_add_warning(user, message); }

// Whether the file name ends in ".obj", in any case.
static bool has_obj_extension(const char *path) {
    size_t n = strlen(path);
    if (n < 4) return false;
    const char *e = path + n - 4;
    return e[0] == '.' && (e[1] | 0x20) == 'o' && (e[2] | 0x20) == 'b' && (e[3] | 0x20) == 'j';
}

/// Turns the material slots of a loaded OBJ into scene materials ("file:name", map_Kd as an image texture)
/// and fills the scene mesh's slot table; *needs_fallback tells whether some faces have no material.
static bool map_obj_materials(sf_loader *ld, jr_val file, const obj_model *model, scene_mesh *sm, bool *needs_fallback) {
    const char *written = file.item->valuestring;
    size_t where = jr_offset(&ld->r, file.tok);
    *needs_fallback = false;
    for (size_t i = 0; i < model->mesh.triangle_count && !*needs_fallback; i++)
        if (model->mesh.triangles[i].material < 0) *needs_fallback = true;
    if (model->material_count && !(sm->slot_material = calloc(model->material_count, sizeof *sm->slot_material)))
        return sf_fail_oom(ld);
    sm->slot_count = model->material_count;
    for (size_t i = 0; i < model->material_count; i++) {
        const obj_material *om = &model->materials[i];
        if (!om->defined) {
            *needs_fallback = true;
            if (!sf_fallback_material(ld, &sm->slot_material[i])) return false;
            continue;
        }
        material m = sf_mtl_material(&om->mtl);
        m.albedo_texture = m.emission_texture = -1;
        // map_Kd is a diffuse colour: it replaces the albedo of Lambertian materials only (a metal's albedo is Ks).
        if (om->diffuse_map && m.kind == MAT_LAMBERTIAN) {
            // The OBJ reader has resolved the path and warned about (and dropped) missing files.
            struct stat st;
            int e = filepath_problem(om->diffuse_map, &st);
            char prefix[512], mesh_path[204], image_path[304];
            snprintf(prefix, sizeof prefix, "mesh file \"%s\": material \"%.100s\": ",
                     filepath_tail(written, 200, mesh_path, sizeof mesh_path), om->name);
            if (e)
                return jr_fail_at(&ld->r, where, "%simage file \"%s\": cannot open: %s", prefix,
                                  filepath_tail(om->diffuse_map, 300, image_path, sizeof image_path), filepath_problem_text(e));
            uint32_t t;
            if (!sf_load_image(ld, where, prefix, om->diffuse_map, om->diffuse_map, (sf_file_id){st.st_dev, st.st_ino},
                               IMAGE_DECODE_SRGB, FILTER_BILINEAR, &t))
                return false;
            m.albedo_texture = (int32_t)t;
        }
        if (!sf_add_file_material(ld, where, written, om->name, &m, &sm->slot_material[i])) return false;
    }
    if (*needs_fallback || sm->slot_count == 0) return sf_fallback_material(ld, &sm->default_material);
    sm->default_material = sm->slot_material[0];
    return true;
}

// Hands a mesh read from file `path` to the scene (ok: it was read; else its arrays are freed) and records it in
// the loader's cache entry, so that placing the file again adds an instance, not a copy.
static bool add_file_mesh(sf_loader *ld, bool ok, scene_mesh *sm, const char *path, sf_file_id id, bool face_normals,
                          sf_mesh_entry *entry) {
    if (ok && !(sm->path = malloc(strlen(path) + 1))) ok = sf_fail_oom(ld);
    if (!ok) {
        mesh_free(&sm->geometry);
        free(sm->slot_material);
        free(sm->path);
        return false;
    }
    memcpy(sm->path, path, strlen(path) + 1);
    long i = scene_add_mesh(ld->scene, sm);
    if (i < 0) return sf_fail_oom(ld);
    *entry = (sf_mesh_entry){id, face_normals, entry->needs_fallback, false, (uint32_t)i};
    return true;
}

/// Loads an OBJ file into a new scene mesh; *entry records it in the cache.
static bool load_mesh(sf_loader *ld, jr_val file, const char *path, sf_file_id id, bool face_normals, sf_mesh_entry *entry) {
    obj_model model;
    glint_error err;
    obj_options opt = {collect_warning, ld, false, false, ld->mesh_threads > 0 ? ld->mesh_threads : -1, 0};
    char got[96], note[420];
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = obj_load(path, &opt, &model, &err);
    if (lane)
        trace_add(lane, &(trace_event){"OBJ read", "load", began, trace_clock(), 2,
                                       {{"file", 0, path},
                                        {"triangles", st == GLINT_OK ? (int64_t)model.mesh.triangle_count : 0, NULL}}});
    if (st != GLINT_OK) {
        jr_fail_at(&ld->r, jr_offset(&ld->r, file.tok), "mesh file %s%s: %s", jr_describe_path(&ld->r, file, got, sizeof got),
                   sf_resolved_note(file.item->valuestring, path, note, sizeof note), err.message);
        ld->r.status = st; // running out of memory stays a resource failure
        return false;
    }
    if (ld->warning_oom) {
        obj_model_free(&model);
        return sf_fail_oom(ld);
    }
    // Its material libraries are inputs too: never overwritten by an image, part of a checkpoint's identity.
    // The keys a library gives that glint does not use are said once, when it first becomes an input.
    for (size_t i = 0; i < model.library_count; i++) {
        const obj_library *lib = &model.libraries[i];
        struct stat sb;
        if (stat(lib->path, &sb) != 0) continue;
        if (lib->unsupported && !scene_reads_file(ld->scene, lib->path)) warn_unsupported_keys(ld, lib);
        if (!scene_add_input(ld->scene, (uint64_t)sb.st_dev, (uint64_t)sb.st_ino, lib->path)) {
            obj_model_free(&model);
            return sf_fail_oom(ld);
        }
    }
    scene_mesh sm = {0};
    bool ok = true;
    if (face_normals) {
        mesh_drop_normals(&model.mesh); // flat shading: every triangle uses its geometric normal
    } else {
        ok = mesh_compute_normals(&model.mesh) || sf_fail_oom(ld);
    }
    ok = ok && map_obj_materials(ld, file, &model, &sm, &entry->needs_fallback);
    // The scene takes the geometry; the model keeps (and frees) its material slots.
    sm.geometry = model.mesh;
    memset(&model.mesh, 0, sizeof model.mesh);
    obj_model_free(&model);
    return add_file_mesh(ld, ok, &sm, path, id, face_normals, entry);
}

// n / |n|, or fallback when n has no direction (or overflows).
static vec3 unit_or(vec3 n, vec3 fallback) {
    float len = v3_len(n);
    return len > 0.0f && isfinite(len) ? v3_scale(n, 1.0f / len) : fallback;
}

// ---------------------------------------------------------------------------------------------
// Meshes from glTF and PLY files (io/model_read): every node's meshes flattened into one mesh

/// The model's placed meshes as one mesh in model space: each placement's vertices moved by its node's transform
/// (normals by the inverse transpose, mirrors keeping their fronts), its triangles in material slot = the model
/// material. Normals and uvs are kept where the file gives them; triangles without are given none.
static bool flatten_model(sf_loader *ld, size_t where, model_file *model, mesh *out) {
    memset(out, 0, sizeof *out);
    // One mesh placed once where it is (every PLY file): taken as it is, not copied.
    if (model->placement_count == 1 && !sf_model_fully_cut(model, &model->meshes[model->placements[0].mesh])) {
        const mat4 id = mat4_identity();
        model_mesh *mm = &model->meshes[model->placements[0].mesh];
        if (memcmp(&model->placements[0].xf, &id, sizeof id) == 0) {
            *out = mm->geometry;
            memset(&mm->geometry, 0, sizeof mm->geometry);
            for (size_t k = 0; k < out->triangle_count; k++) out->triangles[k].material = (int32_t)mm->material;
            return true;
        }
    }
    size_t nv = 0, nt = 0;
    bool any_n = false, all_n = true, any_uv = false;
    for (size_t i = 0; i < model->placement_count; i++) {
        const mesh *g = &model->meshes[model->placements[i].mesh].geometry;
        if (!g->triangle_count || sf_model_fully_cut(model, &model->meshes[model->placements[i].mesh])) continue;
        nv += g->position_count, nt += g->triangle_count;
        any_n |= g->normals != NULL, all_n &= g->normals != NULL, any_uv |= g->uvs != NULL;
        if (nv > (size_t)INT32_MAX || nt > (size_t)INT32_MAX)
            return jr_fail_at(&ld->r, where,
                              "the model's placed meshes flatten to more than 2^31 - 1 vertices or triangles; place it "
                              "with {\"type\": \"import\"}, which keeps repeated meshes as instances");
    }
    if (nv && !(out->positions = malloc(nv * sizeof *out->positions))) return sf_fail_oom(ld);
    if (nt && !(out->triangles = malloc(nt * sizeof *out->triangles))) return sf_fail_oom(ld);
    if (any_n && nv && !(out->normals = malloc(nv * sizeof *out->normals))) return sf_fail_oom(ld);
    if (any_n && !all_n && nt && !(out->normal_corners = malloc(nt * sizeof *out->normal_corners))) return sf_fail_oom(ld);
    if (any_uv && nv && !(out->uvs = malloc(nv * sizeof *out->uvs))) return sf_fail_oom(ld);
    if (any_uv && nt && !(out->uv_corners = malloc(nt * sizeof *out->uv_corners))) return sf_fail_oom(ld);
    size_t v0 = 0, t0 = 0;
    for (size_t i = 0; i < model->placement_count; i++) {
        const model_placement *pl = &model->placements[i];
        const model_mesh *mm = &model->meshes[pl->mesh];
        const mesh *g = &mm->geometry;
        if (!g->triangle_count || sf_model_fully_cut(model, mm)) continue;
        transform xf = transform_identity(); // (used only when invertible; gcc's LTO cannot see that)
        bool invertible = transform_make(&pl->xf, &xf);
        for (size_t k = 0; k < g->position_count; k++) {
            vec3 p = mat4_apply_point(&pl->xf, g->positions[k]);
            if (!v3_is_finite(p) || !invertible)
                return jr_fail_at(&ld->r, where, "the model's node transforms move a vertex beyond single precision");
            out->positions[v0 + k] = p;
            if (any_n) out->normals[v0 + k] = g->normals ? unit_or(mat4_apply_normal(&xf.inv, g->normals[k]), g->normals[k]) : v3s(0.0f);
            if (any_uv) out->uvs[v0 + k] = g->uvs ? g->uvs[k] : (uv2){0.0f, 0.0f};
        }
        bool mirror = mat4_linear_det(&pl->xf) < 0.0;
        for (size_t k = 0; k < g->triangle_count; k++) {
            const int32_t *v = g->triangles[k].v;
            int32_t a = (int32_t)v0 + v[0], b = (int32_t)v0 + v[mirror ? 2 : 1], c = (int32_t)v0 + v[mirror ? 1 : 2];
            out->triangles[t0 + k] = (mesh_triangle){{a, b, c}, (int32_t)mm->material};
            if (out->normal_corners) out->normal_corners[t0 + k] = g->normals ? (mesh_corners){{a, b, c}} : (mesh_corners){{-1, -1, -1}};
            if (any_uv) out->uv_corners[t0 + k] = g->uvs ? (mesh_corners){{a, b, c}} : (mesh_corners){{-1, -1, -1}};
        }
        v0 += g->position_count, t0 += g->triangle_count;
    }
    out->position_count = out->normal_count = out->uv_count = nv;
    if (!any_n) out->normal_count = 0;
    if (!any_uv) out->uv_count = 0;
    if (any_uv && !out->uvs) out->uv_corners = NULL;
    out->triangle_count = nt;
    out->smooth = all_n && any_n; // every vertex has its normal, indexed like its position
    mesh_compute_bounds(out);
    return true;
}

/// Loads a glTF or PLY file into a new scene mesh (flattened); *entry records it in the cache.
static bool load_model_mesh(sf_loader *ld, jr_val file, const char *path, sf_file_id id, bool face_normals,
                            sf_mesh_entry *entry) {
    model_file model;
    if (!sf_model_load(ld, file, path, "mesh", &model)) return false;
    size_t where = jr_offset(&ld->r, file.tok);
    scene_mesh sm = {0};
    bool ok = flatten_model(ld, where, &model, &sm.geometry);
    entry->needs_fallback = false;
    if (ok && model.material_count && !(sm.slot_material = calloc(model.material_count, sizeof *sm.slot_material)))
        ok = sf_fail_oom(ld);
    if (ok) sm.slot_count = model.material_count;
    for (size_t i = 0; ok && i < model.material_count; i++) {
        bool used = false;
        for (size_t p = 0; p < model.placement_count && !used; p++)
            used = model.meshes[model.placements[p].mesh].material == i &&
                   model.meshes[model.placements[p].mesh].geometry.triangle_count;
        if (model.materials[i].is_default || !used) {
            // assimp's stand-in (PLY has no materials): the grey fallback, or the object's "material"
            entry->needs_fallback |= used;
            ok = sf_fallback_material(ld, &sm.slot_material[i]);
        } else {
            ok = sf_model_material(ld, file, &model, i, &sm.slot_material[i]);
        }
    }
    model_file_free(&model);
    if (ok) {
        if (face_normals) mesh_drop_normals(&sm.geometry);
        else if (!(sm.geometry.smooth && !sm.geometry.normal_corners)) // not when every vertex has its normal
            ok = mesh_compute_normals(&sm.geometry) || sf_fail_oom(ld);
    }
    if (ok) ok = sm.slot_count ? (sm.default_material = sm.slot_material[0], true) : sf_fallback_material(ld, &sm.default_material);
    return add_file_mesh(ld, ok, &sm, path, id, face_normals, entry);
}

// Places scene mesh `index` with the object's transform (and transform2) and, when it gives one (`override`), its
// material `mat`; `where` names what is blamed for a mesh out of bounds ("file" or "mesh").
static bool place_mesh(sf_loader *ld, const jr_obj *o, uint32_t index, bool override, uint32_t mat,
                       const transform *xf, bool moved, const char *where) {
    bounds3 ob = ld->scene->meshes[index].geometry.bounds;
    if (!bounds3_is_empty(ob) &&
        !sf_check_extent(ld, jr_member_offset(&ld->r, o, moved ? "transform" : where),
                         moved ? "the transformed mesh" : "the mesh", mat4_apply_bounds(&xf->m, ob)))
        return false;
    uint32_t motion_ref;
    if (!sf_read_motion(ld, o, xf, ob, "mesh", &motion_ref)) return false;
    instance in = {.kind = INSTANCE_MESH, .index = index, .xf = *xf, .material = override ? (int32_t)mat : -1,
                   .motion = motion_ref};
    return scene_add_instance(ld->scene, in) || sf_fail_oom(ld);
}

// A mesh a program added by name (glint_scene_add_mesh), placed like a file's.
static bool read_named_mesh(sf_loader *ld, const jr_obj *o, const char *what, const jr_member *named) {
    char got[96];
    if (jr_get(o, "file"))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "file"),
                          "%s has both \"file\" and \"mesh\"; give one: a mesh file, or a mesh added by name", what);
    if (jr_get(o, "face_normals"))
        return jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, "face_normals"),
                          "\"face_normals\" belongs to a mesh file; a mesh added by name is flat when it was added so");
    if (!cJSON_IsString(named->val.item))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, named->val.tok),
                          "\"mesh\" must be the name of a mesh added with glint_scene_add_mesh, got %s",
                          jr_describe(&ld->r, named->val, got, sizeof got));
    const sf_name *n = sf_names_find(&ld->api_meshes, named->val.item->valuestring);
    if (!n) return sf_fail_undefined(ld, named->val, &ld->api_meshes, "mesh");
    transform xf;
    bool moved, override = jr_get(o, "material") != NULL;
    uint32_t mat = 0;
    if ((override && !sf_read_material_ref(ld, o, what, &mat)) || !sf_read_transform(ld, o, &xf, &moved)) return false;
    return place_mesh(ld, o, n->index, override, mat, &xf, moved, "mesh");
}

// A mesh from a file, placed with its own transform; every mesh object is an instance of its file's mesh,
// which is loaded once however often it is placed.
bool sf_read_mesh(sf_loader *ld, const jr_obj *o, const char *what) {
    const jr_member *named = jr_get(o, "mesh");
    if (named) return read_named_mesh(ld, o, what, named);
    char *path;
    sf_file_id id;
    jr_val file;
    bool face_normals = false, moved;
    transform xf;
    uint32_t mat = 0;
    const bool override = jr_get(o, "material") != NULL;
    if (!sf_read_file_path(ld, o, "file", "mesh", &path, &id, &file)) return false;
    bool ok = true;
    char got[96], note[420];
    const bool is_model = model_format_of(path) != MODEL_FORMAT_NONE;
    if (!has_obj_extension(path) && !is_model)
        ok = jr_fail_at(&ld->r, jr_offset(&ld->r, file.tok),
                        "mesh file %s%s: unsupported format; expected Wavefront OBJ (.obj), glTF 2.0 (.gltf, .glb) or "
                        "PLY (.ply)",
                        jr_describe_path(&ld->r, file, got, sizeof got),
                        sf_resolved_note(file.item->valuestring, path, note, sizeof note));
    ok = ok && jr_read_bool(&ld->r, o, "face_normals", &face_normals) && (!override || sf_read_material_ref(ld, o, what, &mat)) &&
         sf_read_transform(ld, o, &xf, &moved);
    sf_mesh_entry *entry = NULL;
    for (size_t i = 0; ok && i < ld->mesh_count && !entry; i++)
        if (ld->meshes[i].id.dev == id.dev && ld->meshes[i].id.ino == id.ino &&
            ld->meshes[i].face_normals == face_normals)
            entry = &ld->meshes[i];
    if (ok && !entry) {
        if (!array_reserve((void **)&ld->meshes, &ld->mesh_cap, ld->mesh_count + 1, sizeof *ld->meshes)) {
            ok = sf_fail_oom(ld);
        } else {
            entry = &ld->meshes[ld->mesh_count];
            ok = is_model ? load_model_mesh(ld, file, path, id, face_normals, entry)
                          : load_mesh(ld, file, path, id, face_normals, entry);
            if (ok) ld->mesh_count++;
        }
    }
    free(path);
    if (!ok) return false;
    if (!override && entry->needs_fallback && !entry->warned) {
        entry->warned = true;
        sf_warn_at(ld, jr_offset(&ld->r, file.tok),
                   "some faces of mesh file %s have no material (no usemtl, or one no material library defines); they "
                   "are grey Lambertian unless the object gives a \"material\"",
                   jr_describe_path(&ld->r, file, got, sizeof got));
    }
    return place_mesh(ld, o, entry->mesh, override, mat, &xf, moved, "file");
}
