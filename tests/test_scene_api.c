// test_scene_api.c — scenes built call by call through the public API: the book-1 final scene and the bunny from
// arrays render the same bytes as their scene files; every malformed scene of the error table that a call can
// express fails through the calls with the file's message; a failed call leaves the scene as it was; renders
// with per-render overrides and into a caller's buffer.
#include "check.h"
#include "glint.h"
#include "scene_error_cases.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GLINT_SOURCE_DIR
#define GLINT_SOURCE_DIR ".."
#endif

// ---------------------------------------------------------------------------------------------
// Helpers

static char *read_text(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    if (buf) buf[n] = '\0';
    fclose(f);
    return buf;
}

// A copy of v that prints infinite numbers as a file writes them (cJSON prints them as null).
static cJSON *with_infinities(const cJSON *v) {
    if (cJSON_IsNumber(v) && isinf(v->valuedouble)) return cJSON_CreateRaw(v->valuedouble > 0 ? "1e999" : "-1e999");
    cJSON *copy = cJSON_Duplicate(v, 0);
    for (const cJSON *e = v->child; copy && e; e = e->next) {
        cJSON *c = with_infinities(e);
        if (cJSON_IsObject(v)) cJSON_AddItemToObject(copy, e->string, c);
        else cJSON_AddItemToArray(copy, c);
    }
    return copy;
}

// The parameters of a JSON value's text (the test's way of making them from a scene file's parts).
static glint_params *params_of(const cJSON *v) {
    cJSON *printable = with_infinities(v);
    char *text = cJSON_PrintUnformatted(printable);
    cJSON_Delete(printable);
    glint_params *p = NULL;
    glint_error err;
    if (text && glint_params_parse(text, &p, &err) != GLINT_OK) p = NULL;
    free(text);
    return p;
}

// Renders s at a small size with per-render overrides, into a caller's buffer; NULL on failure.
static float *render_small(const glint_scene *s, int w, int h, int spp) {
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = w;
    o.height = h;
    o.spp = spp;
    float *rgb = malloc((size_t)w * (size_t)h * 3 * sizeof *rgb);
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.threads = 2;
    opt.overrides = &o;
    opt.rgb_out = rgb;
    glint_error err;
    if (!rgb || glint_render(s, &opt, NULL, NULL, NULL, NULL, &err) != GLINT_OK) {
        fprintf(stderr, "render failed: %s\n", err.message);
        free(rgb);
        return NULL;
    }
    return rgb;
}

static bool same_floats(const float *a, const float *b, size_t n) { return a && b && memcmp(a, b, n * sizeof *a) == 0; }

// ---------------------------------------------------------------------------------------------
// The book-1 final scene, built from its data with the typed setters

// Sets key to the vector v (3 numbers) of a JSON array.
static void set_vec(glint_params *p, const char *key, const cJSON *v) {
    double x[3];
    for (int i = 0; i < 3; i++) x[i] = cJSON_GetArrayItem(v, i)->valuedouble;
    glint_params_numbers(p, key, x, 3);
}

static void test_rtiow_final(void) {
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/rtiow-final.json", GLINT_SOURCE_DIR);
    char *text = read_text(path);
    CHECK(text != NULL);
    if (!text) return;
    cJSON *root = cJSON_Parse(text);
    glint_scene *from_file = NULL, *built = NULL;
    glint_error err;
    CHECK(glint_scene_load(path, &from_file, &err) == GLINT_OK);
    CHECK(glint_scene_new(path, &built, &err) == GLINT_OK);
    // The render settings and camera, key by key.
    const cJSON *render = cJSON_GetObjectItem(root, "render"), *cam = cJSON_GetObjectItem(root, "camera");
    glint_params *rp = glint_params_new();
    glint_params_number(rp, "width", 1200);
    glint_params_number(rp, "height", 675);
    glint_params_number(rp, "spp", cJSON_GetObjectItem(render, "spp")->valuedouble);
    glint_params_number(rp, "max_depth", 50);
    glint_params_string(rp, "integrator", "path");
    glint_params_string(rp, "background", "sky");
    glint_params_string(rp, "output", "gamma2");
    CHECK(glint_scene_set_render(built, rp, &err) == GLINT_OK);
    glint_params_free(rp);
    glint_params *cp = glint_params_new();
    glint_params_string(cp, "type", "lookat");
    set_vec(cp, "lookfrom", cJSON_GetObjectItem(cam, "lookfrom"));
    set_vec(cp, "lookat", cJSON_GetObjectItem(cam, "lookat"));
    set_vec(cp, "vup", cJSON_GetObjectItem(cam, "vup"));
    glint_params_number(cp, "vfov", cJSON_GetObjectItem(cam, "vfov")->valuedouble);
    glint_params_number(cp, "defocus_angle", cJSON_GetObjectItem(cam, "defocus_angle")->valuedouble);
    glint_params_number(cp, "focus_distance", cJSON_GetObjectItem(cam, "focus_distance")->valuedouble);
    CHECK(glint_scene_set_camera(built, cp, &err) == GLINT_OK);
    glint_params_free(cp);
    // Every sphere with its inline material.
    size_t spheres = 0, failures = 0;
    const cJSON *o;
    cJSON_ArrayForEach(o, cJSON_GetObjectItem(root, "objects")) {
        const cJSON *m = cJSON_GetObjectItem(o, "material");
        glint_params *mp = glint_params_new(), *sp = glint_params_new();
        const char *kind = cJSON_GetObjectItem(m, "type")->valuestring;
        glint_params_string(mp, "type", kind);
        if (strcmp(kind, "dielectric") == 0) {
            glint_params_number(mp, "ior", cJSON_GetObjectItem(m, "ior")->valuedouble);
        } else {
            set_vec(mp, "albedo", cJSON_GetObjectItem(m, "albedo"));
            if (cJSON_GetObjectItem(m, "fuzz")) glint_params_number(mp, "fuzz", cJSON_GetObjectItem(m, "fuzz")->valuedouble);
        }
        glint_params_string(sp, "type", "sphere");
        set_vec(sp, "center", cJSON_GetObjectItem(o, "center"));
        glint_params_number(sp, "radius", cJSON_GetObjectItem(o, "radius")->valuedouble);
        glint_params_object(sp, "material", mp);
        if (glint_scene_add_object(built, sp, &err) != GLINT_OK) {
            if (!failures++) fprintf(stderr, "sphere %zu: %s\n", spheres, err.message);
        }
        spheres++;
        glint_params_free(mp);
        glint_params_free(sp);
    }
    CHECK(spheres == 487 && failures == 0);
    float *a = render_small(from_file, 96, 54, 4), *b = render_small(built, 96, 54, 4);
    CHECK(same_floats(a, b, 96 * 54 * 3));
    free(a);
    free(b);
    glint_scene_free(from_file);
    glint_scene_free(built);
    cJSON_Delete(root);
    free(text);
}

// ---------------------------------------------------------------------------------------------
// The bunny from arrays

// Reads the v and f lines of an OBJ file of triangles (the bunny's), 1-based indices made 0-based.
static bool read_obj_triangles(const char *path, float **pos, size_t *nv, uint32_t **idx, size_t *nt) {
    size_t cv = 0, ct = 0;
    *pos = NULL, *idx = NULL, *nv = *nt = 0;
    FILE *f = fopen(path, "r");
    if (!f) return false;
    char line[512];
    bool ok = true;
    while (ok && fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ') {
            if (*nv == cv) *pos = realloc(*pos, (cv = cv ? 2 * cv : 1024) * 3 * sizeof **pos);
            float *p = *pos + 3 * (*nv)++;
            ok = sscanf(line + 2, "%f %f %f", &p[0], &p[1], &p[2]) == 3;
        } else if (line[0] == 'f' && line[1] == ' ') {
            if (*nt == ct) *idx = realloc(*idx, (ct = ct ? 2 * ct : 1024) * 3 * sizeof **idx);
            uint32_t *t = *idx + 3 * (*nt)++;
            ok = sscanf(line + 2, "%u %u %u", &t[0], &t[1], &t[2]) == 3;
            for (int k = 0; k < 3; k++) t[k]--;
        }
    }
    fclose(f);
    return ok && *nv && *nt;
}

static void test_bunny_arrays(void) {
    char path[512], obj[512];
    snprintf(path, sizeof path, "%s/scenes/bunny.json", GLINT_SOURCE_DIR);
    snprintf(obj, sizeof obj, "%s/scenes/meshes/stanford-bunny/stanford-bunny.obj", GLINT_SOURCE_DIR);
    float *pos = NULL;
    uint32_t *idx = NULL;
    size_t nv = 0, nt = 0;
    CHECK(read_obj_triangles(obj, &pos, &nv, &idx, &nt));
    glint_scene *from_file = NULL, *built = NULL;
    glint_error err;
    CHECK(glint_scene_load(path, &from_file, &err) == GLINT_OK);
    // The scene file's settings, camera, texture and materials by JSON text; the bunny from the arrays.
    glint_params *p;
    CHECK(glint_scene_new(path, &built, &err) == GLINT_OK);
    CHECK(glint_params_parse("{\"width\": 640, \"height\": 480, \"spp\": 128, \"max_depth\": 50, \"integrator\": "
                             "\"path\", \"background\": \"sky\", \"output\": \"gamma2\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_set_render(built, p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"lookat\", \"lookfrom\": [0.6, 1.85, 4.2], \"lookat\": [-0.1, 1, 0], "
                             "\"vup\": [0, 1, 0], \"vfov\": 30}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_set_camera(built, p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"checker\", \"scale\": 0.5, \"even\": [0.8, 0.8, 0.8], \"odd\": [0.3, 0.3, "
                             "0.3]}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_texture(built, "tiles", p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"lambertian\", \"albedo\": \"tiles\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(built, "ground", p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"lambertian\", \"albedo\": [0.75, 0.6, 0.45]}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(built, "clay", p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"quad\", \"q\": [-50, 0.25, 50], \"u\": [100, 0, 0], \"v\": [0, 0, -100], "
                             "\"material\": \"ground\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_object(built, p, &err) == GLINT_OK);
    glint_params_free(p);
    glint_mesh_data md = {.vertex_count = nv, .positions = pos, .triangle_count = nt, .indices = idx};
    CHECK(glint_scene_add_mesh(built, "bunny", &md, &err) == GLINT_OK);
    // The transform by the typed setters: [{"scale": 10}, {"translate": [0.17, -0.08, 0]}].
    p = glint_params_new();
    glint_params *scale = glint_params_new(), *move = glint_params_new();
    glint_params_number(scale, "scale", 10);
    glint_params_numbers(move, "translate", (const double[]){0.17, -0.08, 0}, 3);
    glint_params_string(p, "type", "mesh");
    glint_params_string(p, "mesh", "bunny");
    glint_params_string(p, "material", "clay");
    glint_params_append(p, "transform", scale);
    glint_params_append(p, "transform", move);
    CHECK(glint_scene_add_object(built, p, &err) == GLINT_OK);
    glint_params_free(scale);
    glint_params_free(move);
    glint_params_free(p);
    float *a = render_small(from_file, 64, 48, 2), *b = render_small(built, 64, 48, 2);
    CHECK(same_floats(a, b, 64 * 48 * 3));
    free(a);
    free(b);
    // The mesh's errors name the value.
    uint32_t bad[3] = {0, 1, (uint32_t)nv};
    glint_mesh_data bm = {.vertex_count = nv, .positions = pos, .triangle_count = 1, .indices = bad};
    CHECK(glint_scene_add_mesh(built, "bad", &bm, &err) == GLINT_ERR_INPUT);
    char want[200];
    snprintf(want, sizeof want, "glint_scene_add_mesh: indices[2] (triangle 0) is %zu, but the mesh has %zu vertices",
             nv, nv);
    CHECK(strcmp(err.message, want) == 0);
    CHECK(glint_scene_add_mesh(built, "bunny", &md, &err) == GLINT_ERR_INPUT);
    CHECK(strcmp(err.message, "glint_scene_add_mesh: duplicate mesh name \"bunny\" (defined by an earlier call)") == 0);
    float saved = pos[4];
    pos[4] = INFINITY;
    CHECK(glint_scene_add_mesh(built, "inf", &md, &err) == GLINT_ERR_INPUT);
    CHECK(strcmp(err.message, "glint_scene_add_mesh: positions[4] (vertex 1) is inf; coordinates must be finite") == 0);
    pos[4] = saved;
    CHECK(glint_params_parse("{\"type\": \"mesh\", \"mesh\": \"bunnie\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_object(built, p, &err) == GLINT_ERR_INPUT);
    CHECK(strcmp(err.message, "glint_scene_add_object: mesh \"bunnie\" is not defined (defined: bunny)") == 0);
    glint_params_free(p);
    glint_scene_free(from_file);
    glint_scene_free(built);
    free(pos);
    free(idx);
}

// ---------------------------------------------------------------------------------------------
// The error table through the calls

// The call that reads a value of section `key`, and its function.
static const char *call_of(const char *key) {
    if (strcmp(key, "render") == 0) return "glint_scene_set_render";
    if (strcmp(key, "camera") == 0) return "glint_scene_set_camera";
    if (strcmp(key, "textures") == 0) return "glint_scene_add_texture";
    if (strcmp(key, "materials") == 0) return "glint_scene_add_material";
    if (strcmp(key, "objects") == 0) return "glint_scene_add_object";
    return "glint_scene_add_light";
}

static glint_status call_with(glint_scene *s, const char *key, const char *name, const glint_params *p,
                              glint_error *err) {
    if (strcmp(key, "render") == 0) return glint_scene_set_render(s, p, err);
    if (strcmp(key, "camera") == 0) return glint_scene_set_camera(s, p, err);
    if (strcmp(key, "textures") == 0) return glint_scene_add_texture(s, name, p, err);
    if (strcmp(key, "materials") == 0) return glint_scene_add_material(s, name, p, err);
    if (strcmp(key, "objects") == 0) return glint_scene_add_object(s, p, err);
    return glint_scene_add_light(s, p, err);
}

// Builds the case's scene call by call in the reader's order; 1 when a call failed (its message in *err and the
// call's name in *call), 0 when all passed, -1 when the case is not one calls can express (a syntax error, a
// section that is not an object or array, an element that is not an object, repeated section keys).
static int build_by_calls(const char *text, size_t len, const char **call, glint_error *err) {
    static const char *const order[] = {"render", "camera", "textures", "materials", "objects", "lights"};
    // Text glint's JSON syntax refuses is no value a call could be given.
    char *copy = malloc(len + 1);
    memcpy(copy, text, len);
    copy[len] = '\0';
    glint_params *all = NULL;
    glint_status syntax = strlen(copy) == len ? glint_params_parse(copy, &all, err) : GLINT_ERR_INPUT;
    glint_params_free(all);
    free(copy);
    if (syntax != GLINT_OK) return -1;
    cJSON *root = cJSON_ParseWithLength(text, len);
    if (!root || !cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return -1;
    }
    int verdict = 0;
    for (const cJSON *m = root->child; m && verdict == 0; m = m->next) {
        bool known = false;
        for (size_t k = 0; k < 6; k++) known |= strcmp(m->string, order[k]) == 0;
        int seen = 0;
        for (const cJSON *n = root->child; n; n = n->next) seen += strcmp(n->string, m->string) == 0;
        bool whole = strcmp(m->string, "render") == 0 || strcmp(m->string, "camera") == 0;
        bool shape = whole ? cJSON_IsObject(m) : strcmp(m->string, "objects") == 0 || strcmp(m->string, "lights") == 0
                                                     ? cJSON_IsArray(m) : cJSON_IsObject(m);
        if (!known || seen > 1 || !shape) verdict = -1;
        for (const cJSON *e = whole ? NULL : m->child; e && verdict == 0; e = e->next)
            if (!cJSON_IsObject(e)) verdict = -1;
    }
    glint_scene *s = NULL;
    if (verdict == 0 && glint_scene_new("bad.json", &s, err) != GLINT_OK) verdict = -1;
    for (size_t k = 0; k < 6 && verdict == 0; k++) {
        const cJSON *m = cJSON_GetObjectItemCaseSensitive(root, order[k]);
        if (!m) continue;
        bool whole = k < 2;
        for (const cJSON *e = whole ? m : m->child; e && verdict == 0; e = whole ? NULL : e->next) {
            glint_params *p = params_of(e);
            if (!p) {
                verdict = -1;
                break;
            }
            *call = call_of(order[k]);
            if (call_with(s, order[k], k == 2 || k == 3 ? e->string : NULL, p, err) != GLINT_OK) verdict = 1;
            glint_params_free(p);
        }
    }
    glint_scene_free(s);
    cJSON_Delete(root);
    return verdict;
}

// Removes the clause that says where a name was first defined: in a file, a position in it; through calls, an
// earlier call.
static void drop_first_defined(char *m) {
    static const char *const clauses[] = {" (first defined at ", " (defined by an earlier call)", " (first given at "};
    for (int k = 0; k < 3; k++) {
        char *at = strstr(m, clauses[k]);
        if (!at) continue;
        char *end = strchr(at, ')');
        if (end) memmove(at, end + 1, strlen(end + 1) + 1);
    }
}

// The file's message with "bad.json:LINE:COL: " in place of the call's name; false when it has no such opening.
static bool as_call_message(const char *want, const char *call, char *out, size_t size) {
    const char *p = want;
    if (strncmp(p, "bad.json:", 9) != 0) return false;
    p += 9;
    for (int part = 0; part < 2; part++) {
        if (*p < '0' || *p > '9') return false;
        while (*p >= '0' && *p <= '9') p++;
        if (*p++ != ':') return false;
    }
    if (*p++ != ' ') return false;
    snprintf(out, size, "%s: %s", call, p);
    return true;
}

static void test_error_table(void) {
    size_t expressed = 0, same = 0, spelling = 0;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_scene *c = &cases[i];
        size_t len = c->len ? c->len : strlen(c->text);
        const char *call = NULL;
        glint_error err;
        int r = build_by_calls(c->text, len, &call, &err);
        if (r < 0) continue;
        char want[1200];
        // A number whose spelling alone is wrong (64.00000000000000001 for an integer; 2^53 + 1, which reads as 2^53)
        // has no value a call could be given: as numbers, the calls' values are right.
        if (r == 0) {
            spelling++;
            printf("scene_error_cases.h:%d: a spelling, not a value: %s\n", c->line, c->message);
            continue;
        }
        CHECK(as_call_message(c->message, call, want, sizeof want));
        expressed++;
        drop_first_defined(want);
        drop_first_defined(err.message);
        if (strcmp(err.message, want) == 0) {
            same++;
            continue;
        }
        fprintf(stderr, "scene_error_cases.h:%d:\n  call: %s\n  file: %s\n", c->line, err.message, want);
        CHECK(strcmp(err.message, want) == 0);
    }
    printf("%zu of %zu malformed scenes are calls' values; %zu give the file's message through the calls\n",
           expressed, sizeof cases / sizeof cases[0], same);
    CHECK(expressed > 100 && spelling <= 2);
}

// ---------------------------------------------------------------------------------------------
// What a failed call leaves, names, params, images

static void test_failed_call_leaves_scene(void) {
    glint_scene *s;
    glint_error err;
    glint_params *p;
    CHECK(glint_scene_new(NULL, &s, &err) == GLINT_OK);
    // A sphere whose inline material is fine but whose radius is not: neither is added.
    CHECK(glint_params_parse("{\"type\": \"sphere\", \"center\": [0, 0, -1], \"radius\": 0, \"material\": {\"type\": "
                             "\"lambertian\"}}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_object(s, p, &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "glint_scene_add_object: ") == err.message);
    glint_params_free(p);
    // A render value that fails part-way keeps the settings as they were.
    int w, h;
    CHECK(glint_params_parse("{\"width\": 32, \"height\": 0}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_set_render(s, p, &err) == GLINT_ERR_INPUT);
    glint_params_free(p);
    glint_scene_size(s, &w, &h);
    CHECK(w == 400 && h == 225);
    // A material name taken once stays taken; a failed definition does not take it.
    CHECK(glint_params_parse("{\"type\": \"metal\", \"fuzz\": 2}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(s, "m", p, &err) == GLINT_ERR_INPUT);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"metal\", \"fuzz\": 0.5}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(s, "m", p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(s, "m", p, &err) == GLINT_ERR_INPUT);
    CHECK(strcmp(err.message, "glint_scene_add_material: duplicate material name \"m\" (defined by an earlier call)") == 0);
    CHECK(glint_scene_add_material(s, NULL, p, &err) == GLINT_ERR_INPUT);
    glint_params_free(p);
    // Setters that replace; a non-object text; a bad JSON text.
    p = glint_params_new();
    glint_params_number(p, "radius", 1);
    glint_params_number(p, "radius", 2);
    glint_params_string(p, "type", "sphere");
    glint_params_numbers(p, "center", (const double[]){0, 0, 0}, 3);
    glint_params_string(p, "material", "m");
    CHECK(glint_scene_add_object(s, p, &err) == GLINT_OK);
    glint_params_number(p, "radius", INFINITY);
    CHECK(glint_scene_add_object(s, p, &err) == GLINT_ERR_INPUT);
    glint_params_free(p);
    CHECK(glint_params_parse("[1, 2]", &p, &err) == GLINT_ERR_INPUT && p == NULL);
    CHECK(glint_params_parse("{\"a\": }", &p, &err) == GLINT_ERR_INPUT);
    CHECK(strncmp(err.message, "glint_params_parse:1:7: ", 24) == 0);
    glint_scene_free(s);
}

static void test_image_pixels(void) {
    glint_scene *s;
    glint_error err;
    CHECK(glint_scene_new(NULL, &s, &err) == GLINT_OK);
    // A 2x1 texture: red on the left, blue on the right, sampled with nearest texels on a quad facing the camera.
    const uint8_t bytes[] = {255, 0, 0, 0, 0, 255};
    glint_pixels px = {2, 1, 3, NULL, bytes};
    glint_params *opt;
    CHECK(glint_params_parse("{\"filter\": \"nearest\", \"encoding\": \"linear\"}", &opt, &err) == GLINT_OK);
    CHECK(glint_scene_add_image(s, "rb", &px, opt, &err) == GLINT_OK);
    CHECK(glint_scene_add_image(s, "rb", &px, opt, &err) == GLINT_ERR_INPUT);
    glint_params_free(opt);
    glint_params *p;
    CHECK(glint_params_parse("{\"type\": \"diffuse_light\", \"emission\": \"rb\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(s, "screen", p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"quad\", \"q\": [-1, -1, -1], \"u\": [2, 0, 0], \"v\": [0, 2, 0], "
                             "\"material\": \"screen\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_object(s, p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"integrator\": \"path\", \"width\": 4, \"height\": 4}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_set_render(s, p, &err) == GLINT_OK);
    glint_params_free(p);
    float *rgb = render_small(s, 4, 4, 1);
    CHECK(rgb && rgb[3 * (4 + 0)] == 1.0f && rgb[3 * (4 + 0) + 2] == 0.0f);     // row 1, left: red
    CHECK(rgb && rgb[3 * (4 + 3)] == 0.0f && rgb[3 * (4 + 3) + 2] == 1.0f);     // row 1, right: blue
    free(rgb);
    const float bad[] = {0.5f, NAN, 0.5f};
    glint_pixels bp = {1, 1, 3, bad, NULL};
    CHECK(glint_scene_add_image(s, "nan", &bp, NULL, &err) == GLINT_ERR_INPUT);
    CHECK(strstr(err.message, "values[1] (pixel 0, 0) is nan") != NULL);
    glint_pixels both = {1, 1, 3, bad, bytes};
    CHECK(glint_scene_add_image(s, "both", &both, NULL, &err) == GLINT_ERR_INPUT);
    glint_scene_free(s);
}

// glint_image_from_rgb keeps the caller's values; a loaded scene can be extended by calls.
static void test_image_from_rgb_and_extend(void) {
    const float rgb[] = {0.25f, 0.5f, 2.0f};
    glint_image *img;
    glint_error err;
    CHECK(glint_image_from_rgb(1, 1, rgb, "linear", &img, &err) == GLINT_OK);
    int w, h;
    const float *values;
    glint_image_info(img, &w, &h, &values);
    CHECK(w == 1 && h == 1 && memcmp(values, rgb, sizeof rgb) == 0 && glint_image_byte(img, 0, 0, 2) == 255);
    glint_image_free(img);
    CHECK(glint_image_from_rgb(1, 1, rgb, "gamma3", &img, &err) == GLINT_ERR_INPUT);
    glint_scene *s;
    static const char text[] = "{\"materials\": {\"red\": {\"type\": \"lambertian\", \"albedo\": [1, 0, 0]}}}";
    CHECK(glint_scene_parse("x.json", text, strlen(text), &s, &err) == GLINT_OK);
    glint_params *p;
    CHECK(glint_params_parse("{\"type\": \"sphere\", \"center\": [0, 0, -1], \"radius\": 0.5, \"material\": \"red\"}",
                             &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_object(s, p, &err) == GLINT_OK);
    glint_params_free(p);
    CHECK(glint_params_parse("{\"type\": \"lambertian\"}", &p, &err) == GLINT_OK);
    CHECK(glint_scene_add_material(s, "red", p, &err) == GLINT_ERR_INPUT);
    glint_params_free(p);
    glint_scene_free(s);
}

int main(void) {
    test_failed_call_leaves_scene();
    test_image_pixels();
    test_image_from_rgb_and_extend();
    test_error_table();
    test_bunny_arrays();
    test_rtiow_final();
    return check_summary();
}
