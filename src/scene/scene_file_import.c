// scene_file_import.c — glTF and PLY files (io/model_read) in a scene: their materials as scene materials, a whole
// file as an "import" object (every node's meshes as instances, punctual lights), and a file's camera as the
// scene's ("camera": {"type": "import"}). A model file as a "mesh" object is flattened by scene_file_mesh.c.
#include "scene/scene_file_common.h"
#include "core/array.h"
#include "core/filepath.h"
#include "core/trace.h"
#include "io/model_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// The model reader's callback.
static void collect_warning(const char *message, void *user) { sf_add_warning(user, message); }

bool sf_model_load(sf_loader *ld, jr_val file, const char *path, const char *kind, model_file *model) {
    glint_error err;
    char got[96], note[420];
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = model_read(path, collect_warning, ld, model, &err);
    if (lane) trace_add(lane, &(trace_event){"model read", "load", began, trace_clock(), 1, {{"file", 0, path}}});
    if (st != GLINT_OK) {
        // The reader's message starts with the path it was given: the file is named once, as the scene wrote it.
        size_t n = strlen(path);
        const char *why = strncmp(err.message, path, n) == 0 && err.message[n] == ':' ? err.message + n + 2 : err.message;
        jr_fail_at(&ld->r, jr_offset(&ld->r, file.tok), "%s file %s%s: %s", kind, jr_describe_path(&ld->r, file, got, sizeof got),
                   sf_resolved_note(file.item->valuestring, path, note, sizeof note), why);
        ld->r.status = st; // running out of memory stays a resource failure
        return false;
    }
    if (ld->warning_oom) {
        model_file_free(model);
        return sf_fail_oom(ld);
    }
    // Every file it read (.bin buffers) is an input: never overwritten by an image, part of a checkpoint's identity.
    for (size_t i = 0; i < model->input_count; i++)
        if (!scene_add_input(ld->scene, model->inputs[i].dev, model->inputs[i].ino, model->inputs[i].path)) {
            model_file_free(model);
            return sf_fail_oom(ld);
        }
    return true;
}

// The texture of model image i, decoded as asked: a file through the scene's image cache, embedded bytes here.
static bool model_texture(sf_loader *ld, size_t where, const char *prefix, const model_file *model, int32_t i,
                          image_decode decode, int32_t *out) {
    *out = -1;
    if (i < 0) return true;
    const model_image *im = &model->images[i];
    uint32_t t;
    if (im->path) {
        struct stat st;
        int e = filepath_problem(im->path, &st);
        char shown[304];
        if (e)
            return jr_fail_at(&ld->r, where, "%simage file \"%s\": cannot open: %s", prefix,
                              filepath_tail(im->path, 300, shown, sizeof shown), filepath_problem_text(e));
        if (!sf_load_image(ld, where, prefix, im->path, im->path, (sf_file_id){st.st_dev, st.st_ino}, decode,
                           FILTER_BILINEAR, &t))
            return false;
        *out = (int32_t)t;
        return true;
    }
    if (ld->scene->texture_count >= SF_MAX_ITEMS)
        return jr_fail_at(&ld->r, where, "too many textures (the limit is %d)", SF_MAX_ITEMS);
    image_rgb img;
    glint_error err;
    glint_status st = image_read_memory(im->name, im->data, im->size, decode, &img, &err);
    if (st != GLINT_OK) {
        jr_fail_at(&ld->r, where, "%s%s", prefix, err.message);
        ld->r.status = st;
        return false;
    }
    texture tx = texture_image(img, FILTER_BILINEAR);
    long k = scene_add_texture(ld->scene, &tx, NULL);
    if (k < 0) return sf_fail_oom(ld);
    *out = (int32_t)k;
    return true;
}

bool sf_model_fully_cut(const model_file *model, const model_mesh *placed) {
    const model_material *mm = &model->materials[placed->material];
    return mm->alpha_mode == MODEL_ALPHA_MASK && mm->alpha < mm->alpha_cutoff;
}

bool sf_model_material(sf_loader *ld, jr_val file, const model_file *model, size_t i, uint32_t *index) {
    const model_material *mm = &model->materials[i];
    size_t where = jr_offset(&ld->r, file.tok);
    const char *written = file.item->valuestring;
    char prefix[512], shown[204];
    snprintf(prefix, sizeof prefix, "model file \"%s\": material \"%.100s\": ", filepath_tail(written, 200, shown, sizeof shown),
             mm->name);
    // glTF's metallic-roughness model is glint's pbr, field for field (docs/scene-format.md, "Importing a model").
    material m = material_default(MAT_PBR);
    m.albedo = mm->base_color;
    m.metallic = mm->metallic;
    m.roughness = mm->roughness;
    m.ior = mm->ior;
    m.transmission = mm->transmission;
    m.emission = mm->emission;
    m.normal_scale = mm->normal_scale;
    int32_t metal_rough = -1;
    if (!model_texture(ld, where, prefix, model, mm->base_color_image, IMAGE_DECODE_SRGB, &m.albedo_texture) ||
        !model_texture(ld, where, prefix, model, mm->metallic_roughness_image, IMAGE_DECODE_LINEAR, &metal_rough) ||
        !model_texture(ld, where, prefix, model, mm->normal_image, IMAGE_DECODE_LINEAR, &m.normal_texture) ||
        !model_texture(ld, where, prefix, model, mm->transmission_image, IMAGE_DECODE_LINEAR, &m.transmission_texture) ||
        (v3_max_comp(m.emission) > 0.0f &&
         !model_texture(ld, where, prefix, model, mm->emissive_image, IMAGE_DECODE_SRGB, &m.emission_texture)))
        return false;
    if (m.albedo_texture >= 0) m.base_factor = mm->base_color; // the texture times baseColorFactor, as glTF says
    m.metallic_texture = m.roughness_texture = metal_rough; // glTF: blue is metal, green is roughness
    // MASK: alpha = baseColorFactor.a x the base colour texture's alpha, at most the factor: a factor below the cutoff
    // cuts every fragment (such meshes are never placed: sf_model_fully_cut); otherwise the texture's alpha may cut
    // parts of the surface (material.alpha_cutoff; a texture without alpha cuts nothing, so the mask is left off).
    const texture *base = m.albedo_texture >= 0 ? &ld->scene->textures[m.albedo_texture] : NULL;
    if (mm->alpha_mode == MODEL_ALPHA_MASK && base && base->kind == TEX_IMAGE && base->image.alpha) {
        m.alpha = mm->alpha;
        m.alpha_texture = m.albedo_texture;
        m.alpha_cutoff = mm->alpha_cutoff;
    }
    if (mm->alpha_mode == MODEL_ALPHA_BLEND) {
        char shown2[204];
        sf_warn_at(ld, where, "model file \"%s\": material \"%.100s\": alphaMode BLEND is not supported; rendered opaque",
                   filepath_tail(written, 200, shown2, sizeof shown2), mm->name);
    }
    return sf_add_file_material(ld, where, written, mm->name, &m, index);
}

// ---------------------------------------------------------------------------------------------
// "import": a whole file, its node hierarchy kept

// The scene meshes of every model mesh, their material the model's (or the grey fallback for assimp's stand-in).
static bool add_model_meshes(sf_loader *ld, jr_val file, model_file *model, const char *path, uint32_t *first) {
    *first = (uint32_t)ld->scene->mesh_count;
    uint32_t *materials = model->material_count ? malloc(model->material_count * sizeof *materials) : NULL;
    bool *done = model->material_count ? calloc(model->material_count, sizeof *done) : NULL;
    bool ok = !model->material_count || (materials && done) || sf_fail_oom(ld);
    for (size_t i = 0; ok && i < model->mesh_count; i++) {
        model_mesh *mm = &model->meshes[i];
        uint32_t k = mm->material;
        if (!done[k]) {
            done[k] = true;
            if (model->materials[k].is_default) {
                ok = sf_fallback_material(ld, &materials[k]);
            } else {
                ok = sf_model_material(ld, file, model, k, &materials[k]);
            }
            if (!ok) break;
        }
        scene_mesh sm = {0};
        sm.geometry = mm->geometry;
        memset(&mm->geometry, 0, sizeof mm->geometry);
        sm.default_material = materials[k];
        ok = sm.geometry.smooth || mesh_compute_normals(&sm.geometry) || sf_fail_oom(ld); // the file's, or smooth ones
        if (ok && !(sm.path = malloc(strlen(path) + 1))) ok = sf_fail_oom(ld);
        if (!ok) {
            mesh_free(&sm.geometry);
            free(sm.path);
            break;
        }
        memcpy(sm.path, path, strlen(path) + 1);
        ok = scene_add_mesh(ld->scene, &sm) >= 0 || sf_fail_oom(ld);
    }
    free(materials);
    free(done);
    return ok;
}

// The file's punctual lights, placed by the object's transform.
static bool add_model_lights(sf_loader *ld, size_t where, const model_file *model, const transform *xf) {
    for (size_t i = 0; i < model->light_count; i++) {
        const model_light *ml = &model->lights[i];
        light l = {0};
        l.intensity = ml->intensity;
        l.position = mat4_apply_point(&xf->m, ml->position);
        vec3 d = mat4_apply_vector(&xf->m, ml->direction);
        float len = v3_len(d);
        if (ml->kind != MODEL_LIGHT_POINT && (!(len > 0.0f) || !isfinite(len))) continue;
        d = ml->kind != MODEL_LIGHT_POINT ? v3_scale(d, 1.0f / len) : d;
        switch (ml->kind) {
        case MODEL_LIGHT_POINT: l.kind = LIGHT_POINT; break;
        case MODEL_LIGHT_DIRECTIONAL:
            l.kind = LIGHT_DIRECTIONAL;
            l.direction = v3_neg(d); // glint's points from surfaces towards the light
            break;
        case MODEL_LIGHT_SPOT:
            l.kind = LIGHT_SPOT;
            l.direction = d;
            l.cos_inner = cosf(ml->inner_cone);
            l.cos_outer = cosf(ml->outer_cone);
            break;
        }
        if (l.kind != LIGHT_DIRECTIONAL && !sf_check_extent(ld, where, "an imported light", (bounds3){l.position, l.position}))
            return false;
        if (ld->scene->light_count >= SF_MAX_ITEMS)
            return jr_fail_at(&ld->r, where, "too many lights (the limit is %d)", SF_MAX_ITEMS);
        if (!scene_add_light(ld->scene, l)) return sf_fail_oom(ld);
    }
    return true;
}

bool sf_read_import(sf_loader *ld, const jr_obj *o, const char *what) {
    (void)what;
    char *path;
    sf_file_id id;
    jr_val file;
    transform xf;
    bool moved;
    if (!sf_read_file_path(ld, o, "file", "import", &path, &id, &file)) return false;
    char got[96], note[420];
    if (model_format_of(path) == MODEL_FORMAT_NONE) {
        jr_fail_at(&ld->r, jr_offset(&ld->r, file.tok), "import file %s%s: unsupported format; expected glTF 2.0 (.gltf, "
                   ".glb) or PLY (.ply) (an OBJ file is a {\"type\": \"mesh\"})",
                   jr_describe_path(&ld->r, file, got, sizeof got), sf_resolved_note(file.item->valuestring, path, note, sizeof note));
        free(path);
        return false;
    }
    if (!sf_read_transform(ld, o, &xf, &moved)) {
        free(path);
        return false;
    }
    model_file model;
    bool ok = sf_model_load(ld, file, path, "import", &model);
    uint32_t first = 0;
    // The meshes of a file imported before are placed again, not loaded twice.
    sf_import_entry *entry = NULL;
    for (size_t i = 0; ok && i < ld->import_count && !entry; i++)
        if (ld->imports[i].id.dev == id.dev && ld->imports[i].id.ino == id.ino) entry = &ld->imports[i];
    if (ok && entry) first = entry->first_mesh;
    else if (ok) {
        ok = add_model_meshes(ld, file, &model, path, &first);
        if (ok && !array_reserve((void **)&ld->imports, &ld->import_cap, ld->import_count + 1, sizeof *ld->imports))
            ok = sf_fail_oom(ld);
        if (ok) ld->imports[ld->import_count++] = (sf_import_entry){id, first};
    }
    free(path);
    size_t where = jr_member_offset(&ld->r, o, moved ? "transform" : "file");
    for (size_t i = 0; ok && i < model.placement_count; i++) {
        const model_placement *pl = &model.placements[i];
        const scene_mesh *sm = &ld->scene->meshes[first + pl->mesh];
        if (!sm->geometry.triangle_count || sf_model_fully_cut(&model, &model.meshes[pl->mesh])) continue;
        mat4 m = mat4_mul(&xf.m, &pl->xf);
        transform placed;
        if (!transform_make(&m, &placed)) continue; // a node that scales its mesh to nothing (model_read warned)
        ok = sf_check_extent(ld, where, moved ? "the transformed model" : "the model",
                             mat4_apply_bounds(&placed.m, sm->geometry.bounds));
        if (ok && ld->scene->instance_count >= SF_MAX_ITEMS)
            ok = jr_fail_at(&ld->r, where, "too many objects (the limit is %d)", SF_MAX_ITEMS);
        instance in = {.kind = INSTANCE_MESH, .index = first + pl->mesh, .xf = placed, .material = -1};
        ok = ok && (scene_add_instance(ld->scene, in) || sf_fail_oom(ld));
    }
    ok = ok && add_model_lights(ld, where, &model, &xf);
    model_file_free(&model);
    return ok;
}

// ---------------------------------------------------------------------------------------------
// "camera": {"type": "import", "file": F, "name": N}: a file's perspective camera

static const jr_numspec NUM_TIME = {0.0, 1.0, JR_FLOAT, "a time in [0, 1]"};

bool sf_read_import_camera(sf_loader *ld, const jr_obj *o, camera *c) {
    char *path;
    sf_file_id id;
    jr_val file;
    transform xf;
    bool moved;
    const jr_member *name_m = jr_get(o, "name");
    char got[96];
    if (name_m && (!cJSON_IsString(name_m->val.item)))
        return jr_fail_at(&ld->r, jr_offset(&ld->r, name_m->val.tok), "\"name\" must be a string (a camera's name in "
                          "the file), got %s", jr_describe(&ld->r, name_m->val, got, sizeof got));
    if (!sf_read_transform(ld, o, &xf, &moved) || !sf_read_file_path(ld, o, "file", "camera", &path, &id, &file))
        return false;
    model_file model;
    bool ok = sf_model_load(ld, file, path, "camera", &model);
    free(path);
    if (!ok) return false;
    const model_camera *mc = NULL;
    const char *want = name_m ? name_m->val.item->valuestring : NULL;
    for (size_t i = 0; i < model.camera_count && !mc; i++)
        if (!want || strcmp(model.cameras[i].name, want) == 0) mc = &model.cameras[i];
    if (!mc) {
        char names[300] = "";
        size_t k = 0;
        for (size_t i = 0; i < model.camera_count && k + 2 < sizeof names; i++) {
            int w = snprintf(names + k, sizeof names - k, "%s\"%.60s\"", i ? ", " : "", model.cameras[i].name);
            if (w > 0) k += (size_t)w;
        }
        if (k >= sizeof names) k = sizeof names - 1;
        ok = jr_fail_at(&ld->r, jr_member_offset(&ld->r, o, want ? "name" : "file"),
                        want ? "the file has no camera named \"%s\" (it has: %s)" : "the file has no perspective camera%s%s",
                        want ? want : "", model.camera_count ? names : "none");
        model_file_free(&model);
        return false;
    }
    *c = camera_default();
    c->kind = CAMERA_LOOKAT;
    c->lookfrom = mat4_apply_point(&xf.m, mc->position);
    vec3 fwd = mat4_apply_vector(&xf.m, mc->forward), up = mat4_apply_vector(&xf.m, mc->up);
    c->lookat = v3_add(c->lookfrom, fwd);
    c->vup = up;
    c->vfov_degrees = mc->yfov * (180.0f / 3.14159265358979f);
    model_file_free(&model);
    size_t where = jr_member_offset(&ld->r, o, moved ? "transform" : "file");
    if (!v3_is_finite(c->lookat) || !(v3_len2(v3_sub(c->lookat, c->lookfrom)) > 0.0f) ||
        !(v3_len2(v3_cross(c->vup, v3_sub(c->lookat, c->lookfrom))) > 0.0f))
        return jr_fail_at(&ld->r, where, "the transformed camera has no view direction or no up direction");
    if (!sf_check_extent(ld, where, "the camera", (bounds3){c->lookfrom, c->lookfrom})) return false;
    const jr_member *m = jr_get(o, "shutter");
    if (m) {
        double t[2];
        if (!jr_check_numbers(&ld->r, m->val, "shutter", 2, "2 times [open, close]", &NUM_TIME, t)) return false;
        if (!(t[0] <= t[1]))
            return jr_fail_at(&ld->r, jr_offset(&ld->r, m->val.tok), "\"shutter\" closes before it opens ([%g, %g])", t[0], t[1]);
        c->shutter_open = (float)t[0];
        c->shutter_close = (float)t[1];
    }
    return true;
}
