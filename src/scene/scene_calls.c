// scene_calls.c — a scene built call by call: the scene file's reader (scene_file_*.c) kept alive between calls
// as the scene's session, handed one value a call; triangle and pixel arrays checked here, as the OBJ and image
// readers check what a file holds.
#include "scene/scene_calls.h"
#include "core/array.h"
#include "io/image_read.h"
#include "io/json_scan.h"
#include "scene/scene_file_common.h"

#include <cjson/cJSON.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/// The reader of a scene built call by call, kept between the calls (glint_scene.session).
struct scene_session {
    sf_loader ld;
    glint_error scratch; ///< where the loader writes when no call is running
    size_t objects, lights; ///< values read so far, to number them in messages as a file's are
};

static void session_free(struct scene_session *ss) {
    sf_loader_release(&ss->ld);
    free(ss);
}

// The names a scene already has (a scene read from a file and extended by calls, or built by earlier calls).
static bool names_of(sf_names *t, char *const *names, size_t count) {
    for (size_t i = 0; i < count; i++)
        if (names[i] && !sf_names_find(t, names[i]) && !sf_names_add(t, names[i], (uint32_t)i, UINT32_MAX))
            return false;
    return true;
}

// The scene's session, made on its first call; NULL when out of memory.
static struct scene_session *session_of(glint_scene *s) {
    if (s->session) return s->session;
    struct scene_session *ss = calloc(1, sizeof *ss);
    if (!ss) return NULL;
    sf_loader_init(&ss->ld, s, s->path, 0, &ss->scratch);
    ss->ld.r.call = true;
    // A file's scene keeps its encoding; a new one follows its integrator until a call gives "output".
    ss->ld.output_given = s->material_count || s->sphere_count || s->quad_count || s->instance_count;
    if (!names_of(&ss->ld.materials, s->material_names, s->material_count) ||
        !names_of(&ss->ld.textures, s->texture_names, s->texture_count)) {
        session_free(ss);
        return NULL;
    }
    s->session = ss;
    s->session_free = session_free;
    return ss;
}

static glint_status out_of_memory(const char *call, glint_error *err) {
    return status_fail(err, GLINT_ERR_RENDER, "%s: out of memory", call);
}

// Takes back what a failed call added: the scene's items and the session's caches that point at them.
static void roll_back(struct scene_session *ss, const scene_mark *mark) {
    sf_loader *ld = &ss->ld;
    scene_rollback(ld->scene, mark);
    size_t k = 0;
    for (size_t i = 0; i < ld->image_count; i++)
        if (ld->images[i].texture < mark->textures) ld->images[k++] = ld->images[i];
    ld->image_count = k;
    k = 0;
    for (size_t i = 0; i < ld->mesh_count; i++)
        if (ld->meshes[i].mesh < mark->meshes) ld->meshes[k++] = ld->meshes[i];
    ld->mesh_count = k;
    if (ld->fallback_material >= (long)mark->materials) ld->fallback_material = -1;
}

// Reads `part` from the parsed value v: true when the scene holds it.
static bool read_part(struct scene_session *ss, scene_call_part part, const char *name, jr_val v) {
    sf_loader *ld = &ss->ld;
    sf_names *names = part == SCENE_CALL_TEXTURE ? &ld->textures : &ld->materials;
    const char *kind = part == SCENE_CALL_TEXTURE ? "texture" : "material";
    char shown[SCENE_MAX_NAME + 8], what[64 + SCENE_MAX_NAME];
    uint32_t index;
    switch (part) {
    case SCENE_CALL_RENDER: return sf_read_render(ld, v);
    case SCENE_CALL_CAMERA: return sf_read_camera(ld, v);
    case SCENE_CALL_TEXTURE:
    case SCENE_CALL_MATERIAL:
        snprintf(shown, sizeof shown, "\"%.*s\"", SCENE_MAX_NAME + 2, name);
        if (!sf_check_new_name(ld, names, 0, name, shown, kind)) return false;
        snprintf(what, sizeof what, "%s \"%s\"", kind, name);
        if (!(part == SCENE_CALL_TEXTURE ? sf_read_texture : sf_read_material)(ld, v, what, name, &index)) return false;
        return sf_names_add(names, name, index, UINT32_MAX) || sf_fail_oom(ld);
    case SCENE_CALL_OBJECT: return sf_read_object(ld, v, ss->objects);
    case SCENE_CALL_LIGHT: return sf_read_light(ld, v, ss->lights);
    }
    return false;
}

glint_status scene_call_read(glint_scene *s, scene_call_part part, const char *call, const char *name,
                             const char *json, size_t length, glint_error *err) {
    if ((part == SCENE_CALL_TEXTURE || part == SCENE_CALL_MATERIAL) && !name)
        return status_fail(err, GLINT_ERR_INPUT, "%s: the name must not be NULL", call);
    struct scene_session *ss = session_of(s);
    if (!ss) return out_of_memory(call, err);
    json_index ix;
    json_scan_error se;
    json_result scanned = json_scan(json, length, &ix, &se);
    if (scanned != JSON_SCAN_OK) {
        if (scanned == JSON_SCAN_NOMEM) return out_of_memory(call, err);
        return status_fail(err, GLINT_ERR_INPUT, "%s: %s", call, se.message);
    }
    cJSON *root = cJSON_ParseWithLength(json, length);
    sf_loader *ld = &ss->ld;
    ld->r = (json_reader){call, json, length, &ix, err, GLINT_ERR_INPUT, true};
    scene_mark mark = scene_mark_now(s);
    render_settings settings = s->settings;
    camera cam = s->camera;
    bool output_given = ld->output_given;
    jr_val v;
    bool ok;
    if (!root) ok = sf_fail_oom(ld);
    else ok = jr_root(&ld->r, root, &v) && read_part(ss, part, name, v);
    glint_status status = ok ? GLINT_OK : ld->r.status;
    if (ok) {
        sf_default_output(ld);
        ss->objects += part == SCENE_CALL_OBJECT;
        ss->lights += part == SCENE_CALL_LIGHT;
    } else {
        roll_back(ss, &mark);
        s->settings = settings;
        s->camera = cam;
        ld->output_given = output_given;
    }
    cJSON_Delete(root);
    json_index_free(&ix);
    ld->r = (json_reader){s->path, "", 0, NULL, &ss->scratch, GLINT_ERR_INPUT, true};
    return status;
}

// ---------------------------------------------------------------------------------------------
// Meshes from arrays

// Whether n floats are all finite; *bad is the first that is not.
static bool all_finite(const float *v, size_t n, size_t *bad) {
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) {
            *bad = i;
            return false;
        }
    return true;
}

// Checks the arrays as the OBJ reader checks a file's: counts that fit the mesh's 32-bit indices, finite values,
// indices in range, material names defined. GLINT_OK, or GLINT_ERR_INPUT with the message.
static glint_status check_arrays(const sf_loader *ld, const char *call, const scene_mesh_arrays *a, uint32_t *slots,
                                 glint_error *err) {
    size_t bad;
    if (a->vertex_count > (size_t)INT32_MAX || a->triangle_count > (size_t)INT32_MAX)
        return status_fail(err, GLINT_ERR_INPUT, "%s: %zu vertices and %zu triangles; at most %d of each", call,
                           a->vertex_count, a->triangle_count, INT32_MAX);
    if (a->triangle_count == 0) return status_fail(err, GLINT_ERR_INPUT, "%s: the mesh has no triangles", call);
    if (!a->positions || !a->indices)
        return status_fail(err, GLINT_ERR_INPUT, "%s: positions and indices must not be NULL", call);
    if (!all_finite(a->positions, a->vertex_count * 3, &bad))
        return status_fail(err, GLINT_ERR_INPUT, "%s: positions[%zu] (vertex %zu) is %g; coordinates must be finite",
                           call, bad, bad / 3, (double)a->positions[bad]);
    if (a->normals && a->flat)
        return status_fail(err, GLINT_ERR_INPUT, "%s: a flat mesh takes no normals (each triangle is shaded with its "
                           "geometric normal)", call);
    if (a->normals && !all_finite(a->normals, a->vertex_count * 3, &bad))
        return status_fail(err, GLINT_ERR_INPUT, "%s: normals[%zu] (vertex %zu) is %g; normals must be finite", call,
                           bad, bad / 3, (double)a->normals[bad]);
    if (a->uvs && !all_finite(a->uvs, a->vertex_count * 2, &bad))
        return status_fail(err, GLINT_ERR_INPUT, "%s: uvs[%zu] (vertex %zu) is %g; texture coordinates must be finite",
                           call, bad, bad / 2, (double)a->uvs[bad]);
    for (size_t i = 0; i < a->triangle_count * 3; i++)
        if (a->indices[i] >= a->vertex_count)
            return status_fail(err, GLINT_ERR_INPUT, "%s: indices[%zu] (triangle %zu) is %u, but the mesh has %zu "
                               "vertices", call, i, i / 3, a->indices[i], a->vertex_count);
    if (a->face_materials && (!a->materials || a->material_count == 0))
        return status_fail(err, GLINT_ERR_INPUT, "%s: face_materials need the names of the materials they index",
                           call);
    for (size_t i = 0; a->face_materials && i < a->triangle_count; i++)
        if (a->face_materials[i] >= a->material_count)
            return status_fail(err, GLINT_ERR_INPUT, "%s: face_materials[%zu] is %u, but %zu materials are named",
                               call, i, a->face_materials[i], a->material_count);
    for (size_t i = 0; a->face_materials && i < a->material_count; i++) {
        const sf_name *n = a->materials[i] ? sf_names_find(&ld->materials, a->materials[i]) : NULL;
        if (!n)
            return status_fail(err, GLINT_ERR_INPUT, "%s: materials[%zu], \"%.200s\", is not defined", call, i,
                               a->materials[i] ? a->materials[i] : "(null)");
        slots[i] = n->index;
    }
    return GLINT_OK;
}

// The mesh of the arrays, as the OBJ reader would make it of a file with the same vertices and faces (normals and
// texture coordinates indexed like the positions). False when out of memory.
static bool mesh_of_arrays(const scene_mesh_arrays *a, mesh *m) {
    memset(m, 0, sizeof *m);
    size_t nv = a->vertex_count, nt = a->triangle_count;
    m->positions = malloc((nv ? nv : 1) * sizeof *m->positions);
    m->triangles = malloc(nt * sizeof *m->triangles);
    if (a->normals) m->normals = malloc((nv ? nv : 1) * sizeof *m->normals);
    if (a->uvs) {
        m->uvs = malloc((nv ? nv : 1) * sizeof *m->uvs);
        m->uv_corners = malloc(nt * sizeof *m->uv_corners);
    }
    if (!m->positions || !m->triangles || (a->normals && !m->normals) || (a->uvs && (!m->uvs || !m->uv_corners))) {
        mesh_free(m);
        return false;
    }
    for (size_t i = 0; i < nv; i++) m->positions[i] = v3(a->positions[3 * i], a->positions[3 * i + 1], a->positions[3 * i + 2]);
    m->position_count = nv;
    for (size_t i = 0; i < nt; i++) {
        const uint32_t *t = &a->indices[3 * i];
        m->triangles[i] = (mesh_triangle){{(int32_t)t[0], (int32_t)t[1], (int32_t)t[2]},
                                          a->face_materials ? (int32_t)a->face_materials[i] : -1};
        if (a->uvs) m->uv_corners[i] = (mesh_corners){{(int32_t)t[0], (int32_t)t[1], (int32_t)t[2]}};
    }
    m->triangle_count = nt;
    if (a->normals) {
        for (size_t i = 0; i < nv; i++) m->normals[i] = v3(a->normals[3 * i], a->normals[3 * i + 1], a->normals[3 * i + 2]);
        m->normal_count = nv;
        m->smooth = true;
        m->smooth_base = 0;
    }
    if (a->uvs) {
        for (size_t i = 0; i < nv; i++) m->uvs[i] = (uv2){a->uvs[2 * i], a->uvs[2 * i + 1]};
        m->uv_count = nv;
    }
    mesh_compute_bounds(m);
    return a->flat || mesh_compute_normals(m);
}

glint_status scene_call_add_mesh(glint_scene *s, const char *call, const char *name, const scene_mesh_arrays *a,
                                 glint_error *err) {
    if (!name || !a) return status_fail(err, GLINT_ERR_INPUT, "%s: the name and the mesh must not be NULL", call);
    struct scene_session *ss = session_of(s);
    if (!ss) return out_of_memory(call, err);
    sf_loader *ld = &ss->ld;
    ld->r = (json_reader){call, "", 0, NULL, err, GLINT_ERR_INPUT, true};
    char shown[SCENE_MAX_NAME + 8];
    snprintf(shown, sizeof shown, "\"%.*s\"", SCENE_MAX_NAME + 2, name);
    uint32_t *slots = NULL;
    if (a->face_materials && a->material_count && !(slots = malloc(a->material_count * sizeof *slots)))
        return out_of_memory(call, err);
    glint_status st = GLINT_OK;
    scene_mark mark = scene_mark_now(s);
    if (!sf_check_new_name(ld, &ld->api_meshes, 0, name, shown, "mesh")) st = GLINT_ERR_INPUT;
    if (st == GLINT_OK) st = check_arrays(ld, call, a, slots, err);
    scene_mesh sm = {0};
    if (st == GLINT_OK && !mesh_of_arrays(a, &sm.geometry)) st = out_of_memory(call, err);
    if (st == GLINT_OK && !a->face_materials && !sf_fallback_material(ld, &sm.default_material))
        st = out_of_memory(call, err);
    if (st == GLINT_OK && !(sm.path = malloc(strlen(name) + 1))) st = out_of_memory(call, err);
    if (st == GLINT_OK) {
        memcpy(sm.path, name, strlen(name) + 1);
        sm.slot_material = slots;
        sm.slot_count = a->face_materials ? a->material_count : 0;
        slots = NULL;
        long i = scene_add_mesh(s, &sm); // takes the arrays, and frees them when it fails
        if (i < 0 || !sf_names_add(&ld->api_meshes, name, (uint32_t)i, UINT32_MAX)) st = out_of_memory(call, err);
    } else {
        mesh_free(&sm.geometry);
        free(sm.path);
    }
    free(slots);
    if (st != GLINT_OK) roll_back(ss, &mark);
    ld->r = (json_reader){s->path, "", 0, NULL, &ss->scratch, GLINT_ERR_INPUT, true};
    return st;
}

// ---------------------------------------------------------------------------------------------
// Image textures from pixels

static const char *const image_option_keys[] = {"encoding", "filter", NULL};

glint_status scene_call_add_image(glint_scene *s, const char *call, const char *name, const scene_pixels *px,
                                  const char *options, size_t length, glint_error *err) {
    if (!name || !px) return status_fail(err, GLINT_ERR_INPUT, "%s: the name and the pixels must not be NULL", call);
    if (px->width < 1 || px->height < 1 || (size_t)px->width * (size_t)px->height > IMAGE_READ_MAX_PIXELS)
        return status_fail(err, GLINT_ERR_INPUT, "%s: the image is %d x %d pixels; expected at least 1 x 1 and at "
                           "most %zu pixels, as for image files", call, px->width, px->height, IMAGE_READ_MAX_PIXELS);
    if (px->channels != 1 && px->channels != 3 && px->channels != 4)
        return status_fail(err, GLINT_ERR_INPUT, "%s: %d channels; expected 1 (grey), 3 (RGB) or 4 (RGBA)", call,
                           px->channels);
    if (!px->values == !px->bytes)
        return status_fail(err, GLINT_ERR_INPUT, "%s: give the pixels as floats or as bytes: exactly one of the two",
                           call);
    struct scene_session *ss = session_of(s);
    if (!ss) return out_of_memory(call, err);
    sf_loader *ld = &ss->ld;
    // The options are an image texture's keys, read by the same reader as a file's.
    if (!options) options = "{}", length = 2;
    json_index ix;
    json_scan_error se;
    json_result scanned = json_scan(options, length, &ix, &se);
    if (scanned != JSON_SCAN_OK)
        return scanned == JSON_SCAN_NOMEM ? out_of_memory(call, err)
                                          : status_fail(err, GLINT_ERR_INPUT, "%s: %s", call, se.message);
    cJSON *root = cJSON_ParseWithLength(options, length);
    ld->r = (json_reader){call, options, length, &ix, err, GLINT_ERR_INPUT, true};
    char shown[SCENE_MAX_NAME + 8], what[64 + SCENE_MAX_NAME];
    snprintf(shown, sizeof shown, "\"%.*s\"", SCENE_MAX_NAME + 2, name);
    snprintf(what, sizeof what, "texture \"%s\"", name);
    int encoding = 0, filter = 0;
    jr_val v;
    jr_obj o;
    bool ok = root ? sf_check_new_name(ld, &ld->textures, 0, name, shown, "texture") && jr_root(&ld->r, root, &v) &&
                         jr_open(&ld->r, v, what, image_option_keys, &o) &&
                         jr_read_enum(&ld->r, &o, "encoding", sf_image_encodings, 2, &encoding) &&
                         jr_read_enum(&ld->r, &o, "filter", sf_image_filters, 2, &filter)
                   : sf_fail_oom(ld);
    glint_status st = ok ? GLINT_OK : ld->r.status;
    cJSON_Delete(root);
    json_index_free(&ix);
    ld->r = (json_reader){s->path, "", 0, NULL, &ss->scratch, GLINT_ERR_INPUT, true};
    if (st != GLINT_OK) return st;
    size_t n = (size_t)px->width * (size_t)px->height, c = (size_t)px->channels;
    image_rgb img = {px->width, px->height, malloc(n * 3 * sizeof(float)), NULL};
    if (!img.pixels) return out_of_memory(call, err);
    // RGBA: the alpha channel is coverage (alpha masks), byte / 255 whatever the encoding; kept unless it is 1
    // everywhere, as an image file's.
    bool translucent = false;
    for (size_t i = 0; c == 4 && i < n && !translucent; i++)
        translucent = px->values ? px->values[i * 4 + 3] != 1.0f : px->bytes[i * 4 + 3] != 255;
    if (translucent && !(img.alpha = malloc(n * sizeof(float)))) {
        image_rgb_free(&img);
        return out_of_memory(call, err);
    }
    for (size_t i = 0; img.alpha && i < n; i++) {
        float a = px->values ? px->values[i * 4 + 3] : (float)(px->bytes[i * 4 + 3] / 255.0);
        if (!(a >= 0.0f && a <= 1.0f)) {
            image_rgb_free(&img);
            return status_fail(err, GLINT_ERR_INPUT, "%s: values[%zu] (the alpha of pixel %zu, %zu) is %g; expected a "
                               "value in [0, 1]", call, i * 4 + 3, i % (size_t)px->width, i / (size_t)px->width, (double)a);
        }
        img.alpha[i] = a;
    }
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; k < 3; k++) {
            size_t from = i * c + (c == 1 ? 0 : k);
            float x = px->values ? px->values[from]
                                 : encoding ? (float)(px->bytes[from] / 255.0) : image_srgb_to_linear(px->bytes[from]);
            if (!(x >= 0.0f) || !isfinite(x)) {
                image_rgb_free(&img);
                return status_fail(err, GLINT_ERR_INPUT, "%s: values[%zu] (pixel %zu, %zu) is %g; expected a finite "
                                   "value >= 0", call, from, i % (size_t)px->width, i / (size_t)px->width, (double)x);
            }
            img.pixels[3 * i + k] = x;
        }
    texture t = texture_image(img, filter ? FILTER_NEAREST : FILTER_BILINEAR);
    long index = scene_add_texture(s, &t, name); // takes the pixels, and frees them when it fails
    if (index < 0) return out_of_memory(call, err);
    if (!sf_names_add(&ld->textures, name, (uint32_t)index, UINT32_MAX)) {
        scene_mark mark = scene_mark_now(s);
        mark.textures--;
        scene_rollback(s, &mark);
        return out_of_memory(call, err);
    }
    return GLINT_OK;
}
