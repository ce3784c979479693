// test_obj.c — the OBJ/MTL loader: real meshes load with counts taken independently (awk/Python over the
// files), edge cases from tinyobjloader and assimp, a table of malformed inputs with their exact messages,
// a table of warnings, MTL records and the scene's MTL -> material mapping of them (sf_mtl_material), the MTL
// keys glint does not use, triangulation of concave faces, and the number parser.
#include "check.h"
#include "test_util.h"
#include "core/rng.h"
#include "io/mtl.h"
#include "io/obj.h"
#include "io/obj_parser.h" // the OBJ_MAX_* limits
#include "obj_same.h"
#include "scene/scene_file_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define DATA GLINT_SOURCE_DIR "/tests/data/obj/"

// ---- helpers --------------------------------------------------------------------------------------------

typedef struct warnings {
    char msg[16][1200];
    int count;
} warnings;

static void collect(const char *m, void *user) {
    warnings *w = user;
    if (w->count < 16) snprintf(w->msg[w->count], sizeof w->msg[0], "%s", m);
    w->count++;
}

static void write_text(const char *name, const char *text) { (void)tmp_write(tmp_path(name), text, strlen(text)); }

// `pattern` with every '@' replaced by the temporary directory.
static const char *expand(const char *pattern) {
    static char buf[2048];
    size_t k = 0;
    // The directory may be as long as tmpdir holds (TMPDIR is the user's): leave room for it.
    for (const char *p = pattern; *p && k + sizeof tmpdir + 80 < sizeof buf; p++) {
        if (*p == '@') k += (size_t)snprintf(buf + k, sizeof buf - k, "%s", tmpdir);
        else buf[k++] = *p;
    }
    buf[k] = '\0';
    return buf;
}

// Every line read as a statement, never by a fast path: the tables of cases run both ways.
static bool statements_only;
// Threads and block size of the parallel reader (0, 0: one thread), which every file takes when they are set.
static int load_threads;
static size_t load_block;

static glint_status load(const char *path, obj_model *m, warnings *w, glint_error *err) {
    memset(w, 0, sizeof *w);
    obj_options opt = {collect, w, false, statements_only, load_threads, load_block};
    return obj_load(path, &opt, m, err);
}

// The glint material the scene makes of a slot's MTL values.
static material mapped(const obj_material *om) { return sf_mtl_material(&om->mtl); }

static bool same_string(const char *got, const char *expected) {
    if (strcmp(got, expected) == 0) return true;
    fprintf(stderr, "  got      '%s'\n  expected '%s'\n", got, expected);
    return false;
}

// Area of a triangle and its unit normal, in double.
static double tri_area(const mesh *m, size_t i, double n[3]) {
    vec3 a = m->positions[m->triangles[i].v[0]], b = m->positions[m->triangles[i].v[1]],
         c = m->positions[m->triangles[i].v[2]];
    double u[3] = {(double)b.x - a.x, (double)b.y - a.y, (double)b.z - a.z};
    double v[3] = {(double)c.x - a.x, (double)c.y - a.y, (double)c.z - a.z};
    double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double len = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int k = 0; k < 3; k++) n[k] = len > 0 ? x[k] / len : 0;
    return 0.5 * len;
}

// Newell's vector area of a polygon given by 0-based position indices: half its length is the area.
static void polygon_vector_area(const mesh *m, const int *idx, int n, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    for (int i = 0; i < n; i++) {
        vec3 a = m->positions[idx[i]], b = m->positions[idx[(i + 1) % n]];
        out[0] += 0.5 * ((double)a.y - b.y) * ((double)a.z + b.z);
        out[1] += 0.5 * ((double)a.z - b.z) * ((double)a.x + b.x);
        out[2] += 0.5 * ((double)a.x - b.x) * ((double)a.y + b.y);
    }
}

// A planar polygon is triangulated correctly when its triangles all face the polygon's way and their areas
// add up to its area (an inverted or overlapping triangle would add area twice).
static void check_triangulation(const mesh *m, size_t first, size_t count, const int *idx, int n) {
    double va[3];
    polygon_vector_area(m, idx, n, va);
    double area = sqrt(va[0] * va[0] + va[1] * va[1] + va[2] * va[2]), sum = 0;
    bool facing = true;
    for (size_t i = first; i < first + count; i++) {
        double nn[3];
        sum += tri_area(m, i, nn);
        facing &= nn[0] * va[0] + nn[1] * va[1] + nn[2] * va[2] > 0;
    }
    CHECK(facing);
    CHECK_NEAR(sum, area, 1e-9 + 1e-6 * area);
}

// ---- real meshes ----------------------------------------------------------------------------------------

static void test_cornell_original(void) {
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(DATA "cornell-box-original/CornellBox-Original.obj", &m, &w, &err) == GLINT_OK);
    // awk: v 72, f 18 quads -> 36 triangles; CRLF, tabs, negative indices, Ke light, inline comments.
    CHECK(m.mesh.position_count == 72);
    CHECK(m.mesh.triangle_count == 36);
    CHECK(m.mesh.uv_count == 0 && m.mesh.normal_count == 0);
    CHECK(w.count == 0 && m.warning_count == 0);
    // The first face `f -4 -3 -2 -1` follows the first four vertices: a fan (0,1,2), (0,2,3).
    CHECK(m.mesh.triangles[0].v[0] == 0 && m.mesh.triangles[0].v[1] == 1 && m.mesh.triangles[0].v[2] == 2);
    CHECK(m.mesh.triangles[1].v[0] == 0 && m.mesh.triangles[1].v[1] == 2 && m.mesh.triangles[1].v[2] == 3);
    CHECK(m.mesh.positions[0].x == -1.01f && m.mesh.positions[0].z == 0.99f);
    CHECK(mesh_triangle_normals(&m.mesh, 0).i[0] == -1 && mesh_triangle_uvs(&m.mesh, 0).i[0] == -1);
    static const char *const names[] = {"floor", "ceiling", "backWall", "rightWall", "leftWall", "shortBox", "tallBox", "light"};
    CHECK(m.material_count == 8);
    for (size_t i = 0; i < 8 && i < m.material_count; i++) {
        CHECK(strcmp(m.materials[i].name, names[i]) == 0);
        CHECK(m.materials[i].defined);
        CHECK(m.materials[i].diffuse_map == NULL);
        CHECK(mapped(&m.materials[i]).kind == (i == 7 ? MAT_DIFFUSE_LIGHT : MAT_LAMBERTIAN));
    }
    material lamp = mapped(&m.materials[7]), left = mapped(&m.materials[4]);
    CHECK(lamp.emission.x == 17.0f && lamp.emission.y == 12.0f && lamp.emission.z == 4.0f);
    CHECK(left.albedo.x == 0.63f && left.albedo.y == 0.065f && left.albedo.z == 0.05f);
    CHECK(m.mesh.triangles[0].material == 0);
    CHECK(m.mesh.triangles[35].material == 7); // the light is the last face
    // Bounds from the file (awk): x -1.02..1.00, y 0..1.99, z -1.04..0.99.
    CHECK(m.mesh.bounds.lo.x == -1.02f && m.mesh.bounds.hi.x == 1.0f);
    CHECK(m.mesh.bounds.lo.y == 0.0f && m.mesh.bounds.hi.y == 1.99f);
    CHECK(m.mesh.bounds.lo.z == -1.04f && m.mesh.bounds.hi.z == 0.99f);
    obj_model_free(&m);
}

static void test_spot(void) {
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(DATA "spot/spot_triangulated.obj", &m, &w, &err) == GLINT_OK);
    // awk: v 2930, vt 3225, vn 0, f 5856 triangles `v/vt`; no mtllib.
    CHECK(m.mesh.position_count == 2930 && m.mesh.uv_count == 3225 && m.mesh.normal_count == 0);
    CHECK(m.mesh.triangle_count == 5856);
    CHECK(m.material_count == 0 && w.count == 0);
    bool uv_everywhere = true, no_normals = true, unit_square = true;
    for (size_t i = 0; i < m.mesh.triangle_count; i++)
        for (int k = 0; k < 3; k++) {
            uv_everywhere &= mesh_triangle_uvs(&m.mesh, i).i[k] >= 0;
            no_normals &= mesh_triangle_normals(&m.mesh, i).i[k] == -1;
        }
    for (size_t i = 0; i < m.mesh.uv_count; i++)
        // About the unit square: awk finds 4 of them slightly outside (down to u = -0.052, up to v = 1.00065).
        unit_square &= m.mesh.uvs[i].u >= -0.06f && m.mesh.uvs[i].u <= 1 && m.mesh.uvs[i].v >= 0 && m.mesh.uvs[i].v <= 1.001f;
    CHECK(uv_everywhere && no_normals && unit_square);
    CHECK(m.mesh.triangles[0].material == -1);
    // Smooth normals can be computed for it.
    CHECK(mesh_compute_normals(&m.mesh));
    CHECK(m.mesh.normal_count == 2930 && mesh_triangle_normals(&m.mesh, 5855).i[2] >= 0);
    obj_model_free(&m);
    // The control mesh: 160 quads, 16 pentagons, 4 triangles -> 372 triangles (awk: sum of corners - 2).
    CHECK(load(DATA "spot/spot_control_mesh.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.position_count == 188 && m.mesh.uv_count == 267 && m.mesh.triangle_count == 372);
    CHECK(w.count == 0);
    obj_model_free(&m);
}

static void test_spider(void) {
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(DATA "assimp-spider/spider.obj", &m, &w, &err) == GLINT_OK);
    // awk: v 762, vt 302, vn 747, f 1368 triangles; Python: 56 of them repeat a position (zero area).
    CHECK(m.mesh.position_count == 762 && m.mesh.uv_count == 302 && m.mesh.normal_count == 747);
    CHECK(m.zero_area_faces == 56);
    CHECK(m.mesh.triangle_count == 1368 - 56);
    CHECK(w.count == 2);
    CHECK(same_string(w.msg[0], DATA "assimp-spider/spider.obj:2902: warning: face has zero area; skipped"));
    CHECK(same_string(w.msg[1], DATA "assimp-spider/spider.obj: warning: 56 zero-area faces skipped in total (the first on line 2902)"));
    // Four materials used (Brusttex is defined but never used), every map_Kd a `.\file.jpg` path.
    static const char *const names[] = {"HLeibTex", "Skin", "BeinTex", "Augentex"};
    static const char *const maps[] = {"SpiderTex.jpg", "wal67ar_small.jpg", "drkwood2.jpg", "engineflare1.jpg"};
    CHECK(m.material_count == 4);
    for (size_t i = 0; i < 4 && i < m.material_count; i++) {
        const obj_material *om = &m.materials[i];
        CHECK(strcmp(om->name, names[i]) == 0);
        CHECK(om->defined && mapped(om).kind == MAT_LAMBERTIAN);
        char expect[512];
        snprintf(expect, sizeof expect, "%sassimp-spider/%s", DATA, maps[i]);
        CHECK(om->diffuse_map && same_string(om->diffuse_map, expect));
        CHECK(om->diffuse_map && access(om->diffuse_map, R_OK) == 0);
    }
    CHECK(mapped(&m.materials[1]).albedo.x == 0.827451f);
    bool full = true;
    for (size_t i = 0; i < m.mesh.triangle_count; i++)
        for (int k = 0; k < 3; k++)
            full &= mesh_triangle_uvs(&m.mesh, i).i[k] >= 0 && mesh_triangle_normals(&m.mesh, i).i[k] >= 0;
    CHECK(full);
    obj_model_free(&m);
}

static void test_bunny(void) {
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(DATA "stanford-bunny/stanford-bunny.obj", &m, &w, &err) == GLINT_OK);
    // awk: v 35947, f 69451 triangles (the header says the same).
    CHECK(m.mesh.position_count == 35947 && m.mesh.triangle_count == 69451);
    CHECK(w.count == 0 && m.zero_area_faces == 0);
    // Python (min/max of the coordinates rounded to float).
    CHECK(m.mesh.bounds.lo.x == -0.094690f && m.mesh.bounds.hi.x == 0.061009f);
    CHECK(m.mesh.bounds.lo.y == 0.032987f && m.mesh.bounds.hi.y == 0.187321f);
    CHECK(m.mesh.bounds.lo.z == -0.061874f && m.mesh.bounds.hi.z == 0.058800f);
    obj_model_free(&m);
}

static void test_edge_cases(void) {
    obj_model m;
    warnings w;
    glint_error err;
    // Embree's Cornell box: negative indices, `o` objects, a commented-out face, blank lines with spaces.
    CHECK(load(DATA "tinyobjloader/cornell_box.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.position_count == 76 && m.mesh.triangle_count == 36 && m.material_count == 5 && w.count == 0);
    obj_model_free(&m);
    // Groups with two names; a group without usemtl keeps the previous material.
    CHECK(load(DATA "tinyobjloader/cube.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 12 && m.material_count == 3 && w.count == 0);
    static const int slot[12] = {0, 0, 0, 0, 1, 1, 0, 0, 2, 2, 0, 0}; // white white(inherited) red white green white
    for (int i = 0; i < 12 && (size_t)i < m.mesh.triangle_count; i++) CHECK(m.mesh.triangles[i].material == slot[i]);
    CHECK(mapped(&m.materials[1]).albedo.x == 1.0f && mapped(&m.materials[1]).albedo.y == 0.0f);
    obj_model_free(&m);
    // Full v/vt/vn faces, smoothing groups, indented MTL keys with Tr/Tf/d/Ke.
    CHECK(load(DATA "tinyobjloader/issue-162-smoothing-group.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 12 && m.mesh.uv_count == 4 && m.mesh.normal_count == 6 && w.count == 0);
    CHECK(m.material_count == 2 && mapped(&m.materials[0]).kind == MAT_LAMBERTIAN);
    CHECK(mapped(&m.materials[0]).albedo.x == 0.5f && mapped(&m.materials[1]).albedo.y == 0.5f);
    CHECK(mesh_triangle_uvs(&m.mesh, 2).i[0] == 0 && mesh_triangle_normals(&m.mesh, 2).i[0] == 1);
    obj_model_free(&m);
    // N-gons of 7, 8 and 5 corners; the pentagon repeats a vertex (v19 = v20), so one fan triangle has no
    // area: 5 + 6 + 2 = 13 triangles instead of the 14 of a blind fan.
    CHECK(load(DATA "tinyobjloader/issue-319-002.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 13 && w.count == 0);
    static const int f1[] = {1, 0, 10, 9, 8, 7, 5}, f2[] = {4, 6, 11, 14, 12, 13, 3, 2};
    if (m.mesh.triangle_count == 13) {
        check_triangulation(&m.mesh, 0, 5, f1, 7);
        check_triangulation(&m.mesh, 5, 6, f2, 8);
    }
    obj_model_free(&m);
    CHECK(load(DATA "tinyobjloader/issue-330.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 3 && w.count == 0);
    obj_model_free(&m);
    // A keyhole polygon of 66 corners (two of them repeated): 64 triangles by ear clipping.
    CHECK(load(DATA "assimp/concave_polygon.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 64 && w.count == 0 && m.material_count == 1);
    static const int key[66] = {27, 23, 19, 15, 11, 5,  2,  1,  3,  6,  12, 16, 20, 24, 28, 34, 38,
                                42, 46, 50, 54, 60, 63, 64, 62, 59, 53, 49, 45, 41, 37, 31, 32, 35,
                                39, 43, 47, 51, 55, 57, 61, 58, 56, 52, 48, 44, 40, 36, 33, 30, 26,
                                22, 18, 14, 10, 8,  4,  7,  9,  13, 17, 21, 25, 29, 32, 31};
    int key0[66];
    for (int i = 0; i < 66; i++) key0[i] = key[i] - 1;
    if (m.mesh.triangle_count == 64) check_triangulation(&m.mesh, 0, 64, key0, 66);
    obj_model_free(&m);
    // Lines and points among faces; `usemtl Default` without any mtllib.
    CHECK(load(DATA "assimp/testmixed.obj", &m, &w, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 12 && m.material_count == 1 && !m.materials[0].defined);
    CHECK(mapped(&m.materials[0]).kind == MAT_LAMBERTIAN && mapped(&m.materials[0]).albedo.x == 0.5f);
    CHECK(w.count == 3);
    CHECK(same_string(w.msg[0], DATA "assimp/testmixed.obj:15: warning: 'l' statements are not supported; ignored (reported once)"));
    CHECK(same_string(w.msg[1], DATA "assimp/testmixed.obj:23: warning: 'p' statements are not supported; ignored (reported once)"));
    CHECK(same_string(w.msg[2], DATA "assimp/testmixed.obj:14: warning: material 'Default' is not defined in any material library; using the default material"));
    obj_model_free(&m);
    // The two invalid files of tinyobjloader.
    CHECK(load(DATA "tinyobjloader/invalid-relative-vertex-index.obj", &m, &w, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, DATA "tinyobjloader/invalid-relative-vertex-index.obj:1: vertex index -4 out of range, no vertices defined before this face"));
    CHECK(m.mesh.triangles == NULL && m.materials == NULL);
    CHECK(load(DATA "tinyobjloader/issue-140-zero-face-idx.obj", &m, &w, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, DATA "tinyobjloader/issue-140-zero-face-idx.obj:16: vertex index 0 out of range, expected 1..4 or -4..-1"));
}

// ---- malformed inputs -----------------------------------------------------------------------------------

typedef struct bad_case {
    const char *obj, *mtl; // mtl is written to bad.mtl; the obj refers to it with `mtllib bad.mtl`
    const char *message;   // '@' stands for the temporary directory
} bad_case;

static const bad_case bad_cases[] = {
    {"v 1 2\n", NULL, "@/bad.obj:1: 'v' has 2 numbers, expected 3 (x y z) to 7"},
    {"v 1 2 3 4 5 6 7 8\n", NULL, "@/bad.obj:1: 'v' has 8 numbers, expected 3 (x y z) to 7"},
    {"v 1 2 3\nv 1 2.5.1 3\n", NULL, "@/bad.obj:2: malformed number '2.5.1', expected a decimal number such as -1.25e3"},
    {"v 1,5 2 3\n", NULL, "@/bad.obj:1: malformed number '1,5', expected a decimal number such as -1.25e3"},
    {"v 0x1p3 0 0\n", NULL, "@/bad.obj:1: malformed number '0x1p3', expected a decimal number such as -1.25e3"},
    {"v 1 2 3e\n", NULL, "@/bad.obj:1: malformed number '3e', expected a decimal number such as -1.25e3"},
    {"# comment\r\nv nan 0 0\r\n", NULL, "@/bad.obj:2: 'nan' is not a finite number, expected a decimal number"},
    {"v 0 -inf 0\n", NULL, "@/bad.obj:1: '-inf' is not a finite number, expected a decimal number"},
    {"v 0 0 1.#QNAN\n", NULL, "@/bad.obj:1: '1.#QNAN' is not a finite number, expected a decimal number"},
    {"v 1e39 0 0\n", NULL, "@/bad.obj:1: number '1e39' is out of the range of a float, expected a magnitude below 3.4e38"},
    {"vn 1 0\n", NULL, "@/bad.obj:1: 'vn' has 2 numbers, expected 3 (x y z)"},
    {"vt\n", NULL, "@/bad.obj:1: 'vt' has 0 numbers, expected 1 to 3 (u [v [w]])"},
    {"vt 0.5 0.5 0.5 0.5\n", NULL, "@/bad.obj:1: 'vt' has 4 numbers, expected 1 to 3 (u [v [w]])"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", NULL, "@/bad.obj:4: vertex index 4 out of range, expected 1..3 or -3..-1"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", NULL, "@/bad.obj:4: vertex index 0 out of range, expected 1..3 or -3..-1"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -3 -2\n", NULL, "@/bad.obj:4: vertex index -4 out of range, expected 1..3 or -3..-1"},
    {"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", NULL, "@/bad.obj:1: vertex index 1 out of range, no vertices defined before this face"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 99999999999999999999 1 2\n", NULL,
     "@/bad.obj:4: vertex index 99999999999999999999 out of range, expected 1..3 or -3..-1"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", NULL,
     "@/bad.obj:4: texture coordinate index 1 out of range, no texture coordinates defined before this face"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n", NULL, "@/bad.obj:5: normal index 2 out of range, expected 1..1 or -1..-1"},
    {"v 0 0 0\nv 1 0 0\nf 1 2\n", NULL, "@/bad.obj:3: face has 2 vertices, expected at least 3"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2 3\n", NULL,
     "@/bad.obj:4: malformed face vertex '1/', expected v, v/vt, v//vn or v/vt/vn with integer indices"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n", NULL,
     "@/bad.obj:4: malformed face vertex '1/1/1/1', expected v, v/vt, v//vn or v/vt/vn with integer indices"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n", NULL,
     "@/bad.obj:4: malformed face vertex 'a', expected v, v/vt, v//vn or v/vt/vn with integer indices"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3#x\n", NULL,
     "@/bad.obj:4: malformed face vertex '3#x', expected v, v/vt, v//vn or v/vt/vn with integer indices"},
    {"usemtl\n", NULL, "@/bad.obj:1: 'usemtl' needs a material name"},
    {"mtllib   # no name\n", NULL, "@/bad.obj:1: 'mtllib' needs a file name"},
    {"mtllib bad.mtl\n", "Kd 1 1 1\n", "@/bad.mtl:1: 'Kd' before any 'newmtl', expected 'newmtl name' first"},
    {"mtllib bad.mtl\n", "newmtl\n", "@/bad.mtl:1: 'newmtl' needs a material name"},
    {"mtllib bad.mtl\n", "newmtl a\nKd 1 1\n", "@/bad.mtl:2: 'Kd' has 2 numbers, expected r g b"},
    {"mtllib bad.mtl\n", "newmtl a\r\nKd 1 -1 1\r\n", "@/bad.mtl:2: 'Kd' has a negative component -1, expected values >= 0"},
    {"mtllib bad.mtl\n", "newmtl a\nKe 1 inf 0\n", "@/bad.mtl:2: 'inf' is not a finite number, expected a decimal number"},
    {"mtllib bad.mtl\n", "newmtl a\nd 1.5\n", "@/bad.mtl:2: 'd' is 1.5, expected a value from 0 to 1"},
    {"mtllib bad.mtl\n", "newmtl a\nTr -0.5\n", "@/bad.mtl:2: 'Tr' is -0.5, expected a value from 0 to 1"},
    {"mtllib bad.mtl\n", "newmtl a\nNs -2\n", "@/bad.mtl:2: 'Ns' is -2, expected a value >= 0"},
    {"mtllib bad.mtl\n", "newmtl a\nNi abc\n", "@/bad.mtl:2: malformed number 'abc', expected a decimal number such as -1.25e3"},
    {"mtllib bad.mtl\n", "newmtl a\nillum 11\n", "@/bad.mtl:2: 'illum' is '11', expected an integer from 0 to 10"},
    {"mtllib bad.mtl\n", "newmtl a\nillum 2 3\n", "@/bad.mtl:2: 'illum' has more than one value, expected an integer from 0 to 10"},
    {"mtllib bad.mtl\n", "newmtl a\nmap_Kd -s 1 1 1\n", "@/bad.mtl:2: 'map_Kd' needs a file name"},
};

static void test_malformed(void) {
    int n = (int)(sizeof bad_cases / sizeof bad_cases[0]);
    CHECK(n >= 15);
    for (int i = 0; i < n; i++) {
        const bad_case *c = &bad_cases[i];
        write_text("bad.obj", c->obj);
        write_text("bad.mtl", c->mtl ? c->mtl : "");
        obj_model m;
        warnings w;
        glint_error err;
        glint_status st = load(tmp_path("bad.obj"), &m, &w, &err);
        CHECK(st == GLINT_ERR_INPUT);
        if (st != GLINT_ERR_INPUT) {
            fprintf(stderr, "  case %d loaded\n", i);
            obj_model_free(&m);
            continue;
        }
        if (!same_string(err.message, expand(c->message))) {
            CHECK(false);
            fprintf(stderr, "  in case %d\n", i);
        } else CHECK(true);
        CHECK(m.mesh.positions == NULL && m.mesh.triangle_count == 0 && m.materials == NULL);
    }
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(tmp_path("no-such.obj"), &m, &w, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, expand("@/no-such.obj: cannot open: No such file or directory")));
    CHECK(load(tmpdir, &m, &w, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, expand("@: cannot open: Is a directory")));
}

// ---- warnings -------------------------------------------------------------------------------------------

typedef struct warn_case {
    const char *obj, *mtl;
    size_t triangles;
    const char *messages[3];
} warn_case;

#define TRI "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

static const warn_case warn_cases[] = {
    {TRI "v 2 0 0\nf 1 2 4\nf 1 2 3\nf 1 1 3\n", NULL, 1,
     {"@/w.obj:5: warning: face has zero area; skipped", "@/w.obj: warning: 2 zero-area faces skipped in total (the first on line 5)"}},
    {TRI "v 1 1 0\nf 1 2 4 3\nf 1 2 1 2\n", NULL, 2, {"@/w.obj:6: warning: face has zero area; skipped"}},
    {"mtllib nothere.mtl\n" TRI "f 1 2 3\n", NULL, 1,
     {"@/w.obj:1: warning: cannot open material library 'nothere.mtl' (No such file or directory); its materials are undefined"}},
    // Devices and FIFOs are not directories: say what they are.
    {"mtllib /dev/zero\n" TRI "f 1 2 3\n", NULL, 1,
     {"@/w.obj:1: warning: cannot open material library '/dev/zero' (not a regular file); its materials are undefined"}},
    // A long name keeps its end, where the file name is.
    {"mtllib no/such/directory/of/material/libraries/shapes.mtl\n" TRI "f 1 2 3\n", NULL, 1,
     {"@/w.obj:1: warning: cannot open material library '...rectory/of/material/libraries/shapes.mtl' (No such file or "
      "directory); its materials are undefined"}},
    {TRI "usemtl ghost\nf 1 2 3\n", NULL, 1,
     {"@/w.obj:4: warning: material 'ghost' is not defined in any material library; using the default material"}},
    {"mtllib w.mtl\n" TRI "usemtl a\nf 1 2 3\n", "newmtl a\nmap_Kd nothere.png\n", 1,
     {"@/w.mtl:2: warning: texture 'nothere.png' not found (No such file or directory); material 'a' uses its Kd colour"}},
    {"mtllib w.mtl\n" TRI "f 1 2 3\n", "newmtl a\nnewmtl b\nnewmtl a\nfoo 1\nfoo 2\nKd spectral x.rfl\n", 1,
     {"@/w.mtl:3: warning: material 'a' is defined again; the first definition is used",
      "@/w.mtl:4: warning: 'foo' statements are not supported; ignored (reported once)",
      "@/w.mtl:6: warning: 'Kd spectral' statements are not supported; ignored (reported once)"}},
    {TRI "l 1 2\nl 2 3\ncurv 0 1 1 2\nf 1 2 3\n", NULL, 1,
     {"@/w.obj:4: warning: 'l' statements are not supported; ignored (reported once)",
      "@/w.obj:6: warning: 'curv' statements are not supported; ignored (reported once)"}},
    {"v 1 2 3\n", NULL, 0, {"@/w.obj: warning: no faces; the mesh is empty"}},
    {"", NULL, 0, {"@/w.obj: warning: no faces; the mesh is empty"}},
};

static void test_warnings(void) {
    for (size_t i = 0; i < sizeof warn_cases / sizeof warn_cases[0]; i++) {
        const warn_case *c = &warn_cases[i];
        write_text("w.obj", c->obj);
        write_text("w.mtl", c->mtl ? c->mtl : "");
        obj_model m;
        warnings w;
        glint_error err;
        glint_status st = load(tmp_path("w.obj"), &m, &w, &err);
        CHECK(st == GLINT_OK);
        if (st != GLINT_OK) {
            fprintf(stderr, "  case %zu failed: %s\n", i, err.message);
            continue;
        }
        int expected = 0;
        while (expected < 3 && c->messages[expected]) expected++;
        CHECK(w.count == expected);
        CHECK(m.warning_count == (size_t)expected);
        CHECK(m.mesh.triangle_count == c->triangles);
        for (int k = 0; k < expected && k < w.count; k++) {
            bool ok = same_string(w.msg[k], expand(c->messages[k]));
            CHECK(ok);
            if (!ok) fprintf(stderr, "  in case %zu\n", i);
        }
        obj_model_free(&m);
    }
}

// ---- MTL -> material ------------------------------------------------------------------------------------

typedef struct map_case {
    const char *mtl;
    material_kind kind;
    float a, b, c; // albedo (lambertian, metal, dielectric tint) or emission
    float extra;   // metal fuzz, dielectric ior
} map_case;

static const map_case map_cases[] = {
    {"Kd 0.2 0.4 0.6", MAT_LAMBERTIAN, 0.2f, 0.4f, 0.6f, 0},
    {"Kd 0.25", MAT_LAMBERTIAN, 0.25f, 0.25f, 0.25f, 0},
    {"Ns 10", MAT_LAMBERTIAN, 0.5f, 0.5f, 0.5f, 0},
    {"Kd 0.1 0.1 0.1\nKs 0.9 0.8 0.7\nillum 3\nNs 98", MAT_METAL, 0.9f, 0.8f, 0.7f, 0.14142136f},
    {"illum 5\nKs 1 1 1", MAT_METAL, 1, 1, 1, 0},
    {"illum 8\nKs 2 0.5 0.5\nKd 0 0 0\nNs 0", MAT_METAL, 1, 0.5f, 0.5f, 1},
    {"Kd 0.8 0.8 0.8\nKs 0.3 0.3 0.3\nillum 3", MAT_LAMBERTIAN, 0.8f, 0.8f, 0.8f, 0},
    {"Kd 0.1 0.1 0.1\nKs 0.9 0.9 0.9\nillum 2", MAT_LAMBERTIAN, 0.1f, 0.1f, 0.1f, 0},
    {"d 0.5\nNi 1.33", MAT_DIELECTRIC, 1, 1, 1, 1.33f},
    {"d -halo 0.5", MAT_DIELECTRIC, 1, 1, 1, 1.5f},
    {"illum 7\nNi 2.4\nTf 0.9 1 0.8", MAT_DIELECTRIC, 0.9f, 1, 0.8f, 2.4f},
    {"illum 4", MAT_DIELECTRIC, 1, 1, 1, 1.5f},
    {"Tr 0.3", MAT_DIELECTRIC, 1, 1, 1, 1.5f},
    {"Tr 0.3\nd 1", MAT_LAMBERTIAN, 0.5f, 0.5f, 0.5f, 0},
    {"Ni 0\nd 0.2", MAT_DIELECTRIC, 1, 1, 1, 1.5f},
    {"Ke 17 12 4\nKd 0.78 0.78 0.78", MAT_DIFFUSE_LIGHT, 17, 12, 4, 0},
    {"Ke 0 0 0\nKd 0.5 0.6 0.7\nillum 2", MAT_LAMBERTIAN, 0.5f, 0.6f, 0.7f, 0},
    {"Ke 1 1 1\nd 0.1\nillum 3\nKs 1 1 1", MAT_DIFFUSE_LIGHT, 1, 1, 1, 0},
};

static void test_mapping(void) {
    for (size_t i = 0; i < sizeof map_cases / sizeof map_cases[0]; i++) {
        const map_case *c = &map_cases[i];
        char text[512];
        snprintf(text, sizeof text, "newmtl m\n%s\n", c->mtl);
        mtl_library lib;
        glint_error err;
        CHECK(mtl_parse("x.mtl", text, strlen(text), NULL, &lib, &err) == GLINT_OK);
        CHECK(lib.count == 1);
        if (lib.count != 1) {
            mtl_library_free(&lib);
            continue;
        }
        const material mat = sf_mtl_material(&lib.records[0].values), *m = &mat;
        bool ok = m->kind == c->kind;
        vec3 v = m->kind == MAT_DIFFUSE_LIGHT ? m->emission : m->albedo;
        ok &= fabsf(v.x - c->a) < 1e-6f && fabsf(v.y - c->b) < 1e-6f && fabsf(v.z - c->c) < 1e-6f;
        if (m->kind == MAT_METAL) ok &= fabsf(m->fuzz - c->extra) < 1e-6f;
        if (m->kind == MAT_DIELECTRIC) ok &= fabsf(m->ior - c->extra) < 1e-6f;
        CHECK(ok);
        if (!ok)
            fprintf(stderr, "  mapping case %zu: got %s (%g %g %g) fuzz %g ior %g\n", i, material_kind_name(m->kind),
                    (double)v.x, (double)v.y, (double)v.z, (double)m->fuzz, (double)m->ior);
        CHECK(strcmp(lib.records[0].name, "m") == 0 && lib.records[0].line == 1);
        mtl_library_free(&lib);
    }
}

static void test_texture_paths(void) {
    mtl_options skip = {NULL, NULL, true};
    mtl_library lib;
    glint_error err;
    // Options before the file name are skipped; `\` becomes `/`; paths are relative to the MTL's directory.
    const char *text = "newmtl a\nmap_Kd -s 1 1 1 -o 0 0 -bm 2 -clamp on tex.png\n"
                       "newmtl b\nmap_Kd .\\sub\\tex 2.png\n"
                       "newmtl c\nmap_Kd /abs/t.png # comment\n"
                       "newmtl d\nmap_Kd -s 2 -weird.png\n";
    CHECK(mtl_parse("dir/x.mtl", text, strlen(text), &skip, &lib, &err) == GLINT_OK);
    CHECK(lib.count == 4);
    if (lib.count == 4) {
        CHECK(same_string(lib.records[0].map_kd, "dir/tex.png"));
        CHECK(same_string(lib.records[1].map_kd, "dir/sub/tex 2.png"));
        CHECK(same_string(lib.records[2].map_kd, "/abs/t.png"));
        CHECK(same_string(lib.records[3].map_kd, "dir/-weird.png"));
    }
    mtl_library_free(&lib);
    // A Windows absolute path is retried as the bare file name next to the MTL file.
    write_text("tex.png", "not really a png");
    write_text("win.mtl", "newmtl a\nmap_Kd C:\\Users\\me\\textures\\tex.png\n");
    write_text("win.obj", "mtllib win.mtl\n" TRI "usemtl a\nf 1 2 3\n");
    obj_model m;
    warnings w;
    CHECK(load(tmp_path("win.obj"), &m, &w, &err) == GLINT_OK);
    CHECK(w.count == 0 && m.material_count == 1);
    if (m.material_count == 1) CHECK(m.materials[0].diffuse_map && same_string(m.materials[0].diffuse_map, tmp_path("tex.png")));
    obj_model_free(&m);
}

// The MTL keys glint reads and does not use are not warnings of the reader: the library notes which (one bit
// each, in every block, a dropped duplicate's too) and the line of the first, for the scene's one warning per
// file. `Ka spectral` and unknown keys are the reader's own warnings; used keys are not noted.
static void test_unsupported_keys(void) {
    const char *text = "newmtl a\nNs 10\nNi 1.5\nd 1\nillum 2\nKd 1 1 1\nKs 0 0 0\nKe 0 0 0\nTf 1 1 1\nTr 0\n"
                       "map_Kd t.png\nKa 0.2 0.2 0.2\nbump b.png\nnewmtl b\nKa 1 1 1\nmap_Bump -bm 2 b.png\nPr 0.5\n"
                       "newmtl a\nPm 1\nKa spectral x.rfl\nfoo 1\n";
    warnings w;
    memset(&w, 0, sizeof w);
    mtl_options opt = {collect, &w, true};
    mtl_library lib;
    glint_error err;
    CHECK(mtl_parse("keys.mtl", text, strlen(text), &opt, &lib, &err) == GLINT_OK);
    CHECK(lib.count == 2 && lib.unsupported_line == 12);
    uint32_t expected = 0;
    static const char *const given[] = {"Ka", "bump", "map_Bump", "Pr", "Pm"};
    for (unsigned k = 0; mtl_unsupported_key_name(k); k++)
        for (size_t i = 0; i < sizeof given / sizeof given[0]; i++)
            if (strcmp(mtl_unsupported_key_name(k), given[i]) == 0) expected |= UINT32_C(1) << k;
    CHECK(lib.unsupported == expected && __builtin_popcount(expected) == 5);
    CHECK(w.count == 3 && lib.warning_count == 3);
    CHECK(same_string(w.msg[0], "keys.mtl:18: warning: material 'a' is defined again; the first definition is used"));
    CHECK(same_string(w.msg[1], "keys.mtl:20: warning: 'Ka spectral' statements are not supported; ignored (reported once)"));
    CHECK(same_string(w.msg[2], "keys.mtl:21: warning: 'foo' statements are not supported; ignored (reported once)"));
    mtl_library_free(&lib);
    // Options of used keys are noted too, not the keys.
    text = "newmtl a\nd -halo 1\nmap_Kd -clamp on -s 2 2 t.png\nmap_Kd -weird.png\n";
    CHECK(mtl_parse("opt.mtl", text, strlen(text), &opt, &lib, &err) == GLINT_OK);
    CHECK(lib.count == 1 && lib.unsupported_line == 2 && __builtin_popcount(lib.unsupported) == 2);
    for (unsigned k = 0; k < 32; k++)
        if (lib.unsupported >> k & 1)
            CHECK(strcmp(mtl_unsupported_key_name(k), "d -halo") == 0 ||
                  strcmp(mtl_unsupported_key_name(k), "map_Kd -options") == 0);
    mtl_library_free(&lib);
    // mtl_unsupported_key_name names MTL_UNSUPPORTED_KEYS keys, then none.
    unsigned n = 0;
    while (mtl_unsupported_key_name(n)) n++;
    CHECK(n == MTL_UNSUPPORTED_KEYS);
    // A file with none of them notes none; the OBJ reader passes each library's note on.
    text = "newmtl a\nKd 0.5 0.5 0.5\nillum 2\n";
    CHECK(mtl_parse("none.mtl", text, strlen(text), NULL, &lib, &err) == GLINT_OK);
    CHECK(lib.unsupported == 0 && lib.unsupported_line == 0 && lib.warning_count == 0);
    mtl_library_free(&lib);
    write_text("k1.mtl", "newmtl a\nKd 1 0 0\n");
    write_text("k2.mtl", "newmtl b\nKd 0 1 0\n\nmap_Ks s.png\nKa 0 0 0\n");
    write_text("k.obj", "mtllib k1.mtl k2.mtl\n" TRI "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n");
    obj_model m;
    CHECK(load(tmp_path("k.obj"), &m, &w, &err) == GLINT_OK);
    CHECK(w.count == 0 && m.library_count == 2);
    if (m.library_count == 2) {
        CHECK(same_string(m.libraries[0].path, tmp_path("k1.mtl")) && m.libraries[0].unsupported == 0);
        CHECK(same_string(m.libraries[1].path, tmp_path("k2.mtl")) && m.libraries[1].unsupported_line == 4);
        CHECK(m.libraries[1].unsupported == ((UINT32_C(1) << 0) | (UINT32_C(1) << 10))); // Ka, map_Ks
        CHECK(strcmp(mtl_unsupported_key_name(0), "Ka") == 0 && strcmp(mtl_unsupported_key_name(10), "map_Ks") == 0);
    }
    obj_model_free(&m);
}

// ---- OBJ features ---------------------------------------------------------------------------------------

static void test_index_forms(void) {
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                       "vt 0 0\nvt 1 0\nvt 0 1 0\nvt 1\n"
                       "vn 0 0 1\nvn 0 0 -1\n"
                       "f 1 2 3\n"
                       "f 1/1 2/2 3/3\n"
                       "f 1//1 2//2 3//1\n"
                       "f 1/1/1 2/2/2 3/3/1\n"
                       "f -4/-4/-2 -3/-3/-1 -1/-1/-1\n"
                       "f\t2\t4  3 \r\n";
    obj_model m;
    glint_error err;
    obj_options opt = {NULL, NULL, true, statements_only, 0, 0};
    CHECK(obj_parse("forms.obj", text, strlen(text), &opt, &m, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 6 && m.mesh.uv_count == 4 && m.mesh.normal_count == 2);
    if (m.mesh.triangle_count == 6) {
        const mesh_triangle *t = m.mesh.triangles;
        mesh_corners tc[6], nc[6];
        for (size_t i = 0; i < 6; i++) {
            tc[i] = mesh_triangle_uvs(&m.mesh, i);
            nc[i] = mesh_triangle_normals(&m.mesh, i);
        }
        CHECK(t[0].v[2] == 2 && tc[0].i[0] == -1 && nc[0].i[0] == -1);
        CHECK(tc[1].i[0] == 0 && tc[1].i[2] == 2 && nc[1].i[1] == -1);
        CHECK(tc[2].i[0] == -1 && nc[2].i[1] == 1);
        CHECK(tc[3].i[1] == 1 && nc[3].i[1] == 1 && nc[3].i[2] == 0);
        CHECK(t[4].v[0] == 0 && t[4].v[1] == 1 && t[4].v[2] == 3);
        CHECK(tc[4].i[2] == 3 && nc[4].i[0] == 0 && nc[4].i[2] == 1);
        CHECK(t[5].v[0] == 1 && t[5].v[1] == 3 && t[5].v[2] == 2);
    }
    CHECK(m.mesh.uvs[3].u == 1.0f && m.mesh.uvs[3].v == 0.0f); // `vt u` alone: v = 0
    obj_model_free(&m);
}

static void test_polygons(void) {
    // A convex hexagon: a fan of 4 from its first corner.
    const char *hex = "v 2 0 0\nv 1 1.7 0\nv -1 1.7 0\nv -2 0 0\nv -1 -1.7 0\nv 1 -1.7 0\nf 1 2 3 4 5 6\n";
    obj_model m;
    glint_error err;
    CHECK(obj_parse("hex.obj", hex, strlen(hex), NULL, &m, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == 4);
    static const int hex_idx[6] = {0, 1, 2, 3, 4, 5};
    if (m.mesh.triangle_count == 4) {
        check_triangulation(&m.mesh, 0, 4, hex_idx, 6);
        for (int i = 0; i < 4; i++) CHECK(m.mesh.triangles[i].v[0] == 0);
    }
    obj_model_free(&m);
    // Concave: an L in the y-z plane (listed clockwise seen from +x), a dart quad, a U, a comb.
    static const struct { const char *obj; int n; size_t tris; } shapes[] = {
        {"v 0 0 0\nv 0 0 2\nv 0 1 2\nv 0 1 1\nv 0 2 1\nv 0 2 0\nf 1 2 3 4 5 6\n", 6, 4},
        {"v 0 0 0\nv 2 1 0\nv 0 2 0\nv 0.5 1 0\nf 1 2 3 4\n", 4, 2},
        {"v 0 0 0\nv 3 0 0\nv 3 3 0\nv 2 3 0\nv 2 1 0\nv 1 1 0\nv 1 3 0\nv 0 3 0\nf 1 2 3 4 5 6 7 8\n", 8, 6},
        {"v 0 0 5\nv 4 0 5\nv 4 3 5\nv 3.5 1 5\nv 3 3 5\nv 2.5 1 5\nv 2 3 5\nv 1.5 1 5\nv 1 3 5\nv 0.5 1 5\nv 0 3 5\n"
         "f 1 2 3 4 5 6 7 8 9 10 11\n", 11, 9},
        {"v 0 0 0\nv 0 0 2\nv 0 1 2\nv 0 1 1\nv 0 2 1\nv 0 2 0\nf -1 -2 -3 -4 -5 -6\n", 6, 4}, // reversed winding
    };
    for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
        CHECK(obj_parse("c.obj", shapes[s].obj, strlen(shapes[s].obj), NULL, &m, &err) == GLINT_OK);
        CHECK(m.mesh.triangle_count == shapes[s].tris);
        int idx[16];
        for (int i = 0; i < shapes[s].n; i++) idx[i] = s == 4 ? shapes[s].n - 1 - i : i;
        if (m.mesh.triangle_count == shapes[s].tris) check_triangulation(&m.mesh, 0, shapes[s].tris, idx, shapes[s].n);
        obj_model_free(&m);
    }
    // A concave face above the ear-clipping limit: a fan, with a warning.
    enum { N = OBJ_MAX_EAR_CLIP + 44 };
    size_t cap = (size_t)N * 64 + 64, k = 0;
    char *big = malloc(cap);
    for (int i = 0; i < N; i++) {
        double a = 2 * 3.14159265358979 * i / N, r = i % 2 ? 1.0 : 2.0; // a star: every other corner reflex
        k += (size_t)snprintf(big + k, cap - k, "v %.6f %.6f 0\n", r * cos(a), r * sin(a));
    }
    k += (size_t)snprintf(big + k, cap - k, "f");
    for (int i = 1; i <= N; i++) k += (size_t)snprintf(big + k, cap - k, " %d", i);
    snprintf(big + k, cap - k, "\n");
    warnings w;
    memset(&w, 0, sizeof w);
    obj_options opt = {collect, &w, false, false, 0, 0};
    CHECK(obj_parse("star.obj", big, strlen(big), &opt, &m, &err) == GLINT_OK);
    CHECK(m.mesh.triangle_count == N - 2);
    CHECK(w.count == 1 && same_string(w.msg[0], "star.obj:301: warning: concave face with 300 vertices triangulated as a fan; it may be wrong"));
    obj_model_free(&m);
    free(big);
}

// A convex polygon above the ear-clipping limit whose corners, rounded to float, make tiny dents: a fan
// without a warning (it is not concave; the fan is right). Written with 9 digits, as exact as a float.
static void test_large_convex_face(void) {
    enum { N = 100000 };
    size_t cap = (size_t)N * 48 + 64, k = 0;
    char *text = malloc(cap);
    CHECK(text != NULL);
    if (!text) return;
    for (int i = 0; i < N; i++) {
        double a = 2 * 3.14159265358979 * i / N;
        k += (size_t)snprintf(text + k, cap - k, "v %.9g %.9g 0\n", 3.0 + cos(a), 5.0 + sin(a));
    }
    k += (size_t)snprintf(text + k, cap - k, "f");
    for (int i = 1; i <= N; i++) k += (size_t)snprintf(text + k, cap - k, " %d", i);
    snprintf(text + k, cap - k, "\n");
    warnings w;
    memset(&w, 0, sizeof w);
    obj_options opt = {collect, &w, false, false, 0, 0};
    obj_model m;
    glint_error err;
    CHECK(obj_parse("circle.obj", text, strlen(text), &opt, &m, &err) == GLINT_OK);
    // A fan of N - 2 triangles, less the few that rounding made exactly flat (dropped: they have no area).
    CHECK(m.mesh.triangle_count > N - 100 && m.mesh.triangle_count <= N - 2);
    CHECK(w.count == 0);
    if (w.count) fprintf(stderr, "  warning: %s\n", w.msg[0]);
    obj_model_free(&m);
    free(text);
}

// Lines, faces and files beyond the documented limits of obj.h: refused with the limit named, before
// anything in proportion to them is allocated.
static void test_limits(void) {
    obj_model m;
    glint_error err;
    // A face of OBJ_MAX_FACE_CORNERS + 1 corners.
    size_t n = (size_t)OBJ_MAX_FACE_CORNERS + 1, len = 0;
    char *text = malloc(2 * n + 64);
    CHECK(text != NULL);
    if (!text) return;
    len += (size_t)snprintf(text, 64, "%sf", TRI);
    for (size_t i = 0; i < n; i++) {
        text[len++] = ' ';
        text[len++] = '1';
    }
    CHECK(obj_parse("big.obj", text, len, NULL, &m, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, "big.obj:4: face has more than 1048576 vertices, expected at most 1048576"));
    free(text);
    // A line of OBJ_MAX_LINE_BYTES + 1 bytes (a comment: it would cost nothing, but no real file has one).
    n = OBJ_MAX_LINE_BYTES + 1;
    text = malloc(n + 16);
    CHECK(text != NULL);
    if (!text) return;
    memcpy(text, "v 0 0 0\n#", 9);
    memset(text + 9, 'x', n - 1);
    CHECK(obj_parse("long.obj", text, n + 8, NULL, &m, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, "long.obj:2: line is 33554433 bytes long, expected at most 33554432 (32 MiB)"));
    free(text);
    // Files over the size limits (sparse: no disk space is used), refused before they are read.
    FILE *f = fopen(tmp_path("huge.obj"), "wb");
    CHECK(f && ftruncate(fileno(f), (off_t)OBJ_MAX_FILE_BYTES + 1) == 0);
    if (f) fclose(f);
    warnings w;
    CHECK(load(tmp_path("huge.obj"), &m, &w, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, expand("@/huge.obj: the OBJ file is larger than 2147483648 bytes (2 GiB)")));
    remove(tmp_path("huge.obj"));
    f = fopen(tmp_path("huge.mtl"), "wb");
    CHECK(f && ftruncate(fileno(f), (off_t)MTL_MAX_FILE_BYTES + 1) == 0);
    if (f) fclose(f);
    write_text("lib.obj", "mtllib huge.mtl\n" TRI "f 1 2 3\n");
    CHECK(load(tmp_path("lib.obj"), &m, &w, &err) == GLINT_ERR_INPUT);
    CHECK(same_string(err.message, expand("@/lib.obj:1: material library 'huge.mtl' is larger than 67108864 bytes (64 MiB)")));
    remove(tmp_path("huge.mtl"));
}

static void test_materials_in_obj(void) {
    // usemtl before mtllib, two libraries on one line, a library whose name has a space, repeated mtllib,
    // faces before any usemtl, and a name defined in two libraries (the first wins).
    write_text("one.mtl", "newmtl red\nKd 1 0 0\nnewmtl both\nKd 0.1 0.1 0.1\n");
    write_text("two.mtl", "newmtl green\nKd 0 1 0\nnewmtl both\nKd 0.9 0.9 0.9\n");
    write_text("my lib.mtl", "newmtl lamp\nKe 5 5 5\n");
    write_text("m.obj", TRI "f 1 2 3\nusemtl green\nf 1 2 3\nmtllib one.mtl two.mtl\nmtllib one.mtl\n"
                        "mtllib my lib.mtl\nusemtl red\nf 1 2 3\nusemtl both\nf 1 2 3\nusemtl lamp\nf 1 2 3\n"
                        "usemtl green\nf 1 2 3\n");
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(tmp_path("m.obj"), &m, &w, &err) == GLINT_OK);
    CHECK(w.count == 0);
    CHECK(m.material_count == 4 && m.mesh.triangle_count == 6);
    if (m.material_count == 4 && m.mesh.triangle_count == 6) {
        static const int slots[6] = {-1, 0, 1, 2, 3, 0};
        for (int i = 0; i < 6; i++) CHECK(m.mesh.triangles[i].material == slots[i]);
        CHECK(strcmp(m.materials[0].name, "green") == 0 && mapped(&m.materials[0]).albedo.y == 1.0f);
        CHECK(mapped(&m.materials[1]).albedo.x == 1.0f);
        CHECK(mapped(&m.materials[2]).albedo.x == 0.1f);
        CHECK(mapped(&m.materials[3]).kind == MAT_DIFFUSE_LIGHT);
        CHECK(m.materials[0].line == 5 && m.materials[3].line == 14);
    }
    obj_model_free(&m);
    // skip_files: libraries are not opened and nothing is reported about them.
    const char *text = "mtllib nothere.mtl\nusemtl x\n" TRI "f 1 2 3\n";
    memset(&w, 0, sizeof w);
    obj_options opt = {collect, &w, true, false, 0, 0};
    CHECK(obj_parse("mem.obj", text, strlen(text), &opt, &m, &err) == GLINT_OK);
    CHECK(w.count == 1 && same_string(w.msg[0], "mem.obj:2: warning: material 'x' is not defined in any material library; using the default material"));
    obj_model_free(&m);
}

static void test_comments_and_blanks(void) {
    const char *text = "# header\n   # indented comment\n\t\n\nv 0 0 0 # inline\nv 1 0 0\t\r\nv 0 1 0 1.0\nv 0 0 1 0.5 0.5 0.5\n"
                       "o thing\ng a b  c\ns off\ns 1\nf 1 2 3 # comment\nf 1 3 4";
    obj_model m;
    glint_error err;
    warnings w;
    memset(&w, 0, sizeof w);
    obj_options opt = {collect, &w, false, false, 0, 0};
    CHECK(obj_parse("c.obj", text, strlen(text), &opt, &m, &err) == GLINT_OK);
    CHECK(m.mesh.position_count == 4 && m.mesh.triangle_count == 2 && w.count == 0);
    obj_model_free(&m);
}

// ---- numbers --------------------------------------------------------------------------------------------

// Every coordinate the loader reads equals strtof's reading of the same text, bit for bit.
static void test_numbers_match_strtof(void) {
    rng r = rng_for_sample(2024, 0, 0);
    enum { LINES = 40000 };
    size_t cap = (size_t)LINES * 3 * 48 + 1024, k = 0;
    char *text = malloc(cap);
    char (*tokens)[48] = malloc((size_t)LINES * 3 * sizeof *tokens);
    static const char *const fixed[] = {"0", "-0", "+.5", "5.", "1E+3", "1e-45", "1.4e-45", "7e-46", "3.4028235e38",
                                        "3.40282356e38", "1.17549435e-38", "0.000000000000000000000000000000000001",
                                        "123456789012345678901234567890", "0.1", "0.30000000000000004",
                                        "16777217", "16777219", "2.5e-40", "-1e-320", "9007199254740993",
                                        "1.00000005960464477539062500001", "1.000000059604644775390625"};
    int nfixed = (int)(sizeof fixed / sizeof fixed[0]);
    for (int i = 0; i < LINES * 3; i++) {
        char *t = tokens[i];
        int mode = i < nfixed ? -1 : (int)(rng_u32(&r) % 6);
        uint32_t bits = rng_u32(&r);
        float f;
        memcpy(&f, &bits, sizeof f);
        if (!isfinite(f)) f = 1.5f;
        double d = (double)rng_u32(&r) / 4294967296.0 * 2000.0 - 1000.0;
        switch (mode) {
        case -1: snprintf(t, 48, "%s", fixed[i]); break;
        case 0: snprintf(t, 48, "%.9g", (double)f); break;     // any float, round trip
        case 1: snprintf(t, 48, "%.6f", d); break;             // OBJ exporters' style
        case 2: snprintf(t, 48, "%.17g", d); break;            // more digits than a float holds
        case 3: snprintf(t, 48, "%.8e", (double)f); break;
        case 4: snprintf(t, 48, "%d", (int)(rng_u32(&r) % 2000000) - 1000000); break;
        default: snprintf(t, 48, "%.3g", d * 1e-3); break;
        }
    }
    for (int i = 0; i < LINES; i++)
        k += (size_t)snprintf(text + k, cap - k, "v %s %s %s\n", tokens[3 * i], tokens[3 * i + 1], tokens[3 * i + 2]);
    obj_model m;
    glint_error err;
    glint_status st = obj_parse("n.obj", text, k, NULL, &m, &err);
    CHECK(st == GLINT_OK);
    if (st != GLINT_OK) fprintf(stderr, "%s\n", err.message);
    int mismatches = 0;
    for (int i = 0; st == GLINT_OK && i < LINES * 3; i++) {
        vec3 p = m.mesh.positions[i / 3];
        float got = i % 3 == 0 ? p.x : i % 3 == 1 ? p.y : p.z, want = strtof(tokens[i], NULL);
        if (memcmp(&got, &want, sizeof got) != 0) {
            if (mismatches++ < 5) fprintf(stderr, "  '%s': got %.9g, strtof %.9g\n", tokens[i], (double)got, (double)want);
        }
    }
    CHECK(mismatches == 0);
    if (st == GLINT_OK) obj_model_free(&m);
    free(text);
    free(tokens);
}

// ---- reading a file in blocks; the mesh against a plain strtof reader ---------------------------------

// A growable text for the tests below.
typedef struct text_buf {
    char *s;
    size_t n, cap;
} text_buf;

static void put_n(text_buf *t, const char *s, size_t k) {
    if (t->n + k + 1 > t->cap) {
        size_t cap = (t->n + k + 1) * 2;
        char *grown = realloc(t->s, cap);
        if (!grown) return;
        t->s = grown;
        t->cap = cap;
    }
    memcpy(t->s + t->n, s, k);
    t->n += k;
    t->s[t->n] = '\0';
}

static void put(text_buf *t, const char *s) { put_n(t, s, strlen(s)); }

// A file of line 1 "v 0 0 0", line 2 a comment of `length` bytes, then `tail`.
static bool write_long_line(const char *path, size_t length, const char *tail) {
    size_t n = 8 + length + strlen(tail);
    char *text = malloc(n);
    if (!text) return false;
    memcpy(text, "v 0 0 0\n", 8);
    text[8] = '#';
    memset(text + 9, 'x', length - 1);
    memcpy(text + 8 + length, tail, strlen(tail));
    bool ok = tmp_write(path, text, n);
    free(text);
    return ok;
}

// obj_load reads a file in blocks of a few hundred KiB and parses each block's complete lines as it comes:
// whatever falls on a block's edge (a line, a CRLF, a line longer than a block, the last line without an
// end), the model, the warnings and the errors are those of obj_parse over the whole text (run a second
// time with obj_load reading statements only: then the fast paths are checked against the statements too).
static void test_blocks_match_whole_text(void) {
    text_buf t = {0};
    rng r = rng_for_sample(77, 1, 0);
    char line[256];
    int nv = 0, nt = 0, nn = 0;
    for (int i = 0; i < 60000; i++) {
        uint32_t u = rng_u32(&r) % 100;
        const char *eol = u % 7 == 0 ? "\r\n" : "\n";
        if (u < 40 || nv < 3) {
            snprintf(line, sizeof line, "v %.6f %.9g %g%s", (double)rng_range(&r, -9, 9), (double)rng_range(&r, -1, 1),
                     (double)rng_float(&r), eol);
            nv++;
        } else if (u < 45) {
            snprintf(line, sizeof line, "vt %.4f %.4f%s", (double)rng_float(&r), (double)rng_float(&r), eol);
            nt++;
        } else if (u < 50) {
            snprintf(line, sizeof line, "vn %.3f 0.5 %.3f%s", (double)rng_range(&r, -1, 1), (double)rng_range(&r, -1, 1), eol);
            nn++;
        } else if (u < 90) {
            int a = 1 + (int)(rng_u32(&r) % (uint32_t)nv), b = 1 + (int)(rng_u32(&r) % (uint32_t)nv);
            int c = -1 - (int)(rng_u32(&r) % 3);
            if (nt && nn) snprintf(line, sizeof line, "f %d/%d/%d %d//%d %d/-1%s", a, 1 + a % nt, 1 + a % nn, b, 1 + b % nn, c, eol);
            else snprintf(line, sizeof line, "f %d %d %d%s", a, b, c, eol);
        } else if (u < 93) {
            snprintf(line, sizeof line, "usemtl m%u%s", rng_u32(&r) % 4, eol);
        } else if (u < 96) {
            snprintf(line, sizeof line, "# comment %u%s", rng_u32(&r), eol);
        } else if (u < 98) {
            snprintf(line, sizeof line, "%s", eol);
        } else {
            snprintf(line, sizeof line, "f %d %d %d 1 # a quad%s", nv, nv - 1, nv - 2, eol);
        }
        put(&t, line);
        if (i == 30000) {
            // A face of 200000 corners (1.4 MB: several blocks) around a circle.
            for (int k = 0; k < 200000; k++) {
                double a = 6.283185307179586 * k / 200000;
                snprintf(line, sizeof line, "v %.7f %.7f 0\n", cos(a), sin(a));
                put(&t, line);
            }
            nv += 200000;
            put(&t, "f");
            for (int k = 0; k < 200000; k++) {
                snprintf(line, sizeof line, " %d", k - 200000);
                put(&t, line);
            }
            put(&t, "\n");
        }
    }
    put(&t, "f 1 2 3"); // no line end
    const char *path = tmp_path("blocks.obj");
    CHECK(t.s && tmp_write(path, t.s, t.n));
    if (!t.s) return;
    obj_model whole, blocks;
    warnings w1, w2;
    glint_error err;
    memset(&w1, 0, sizeof w1);
    obj_options opt = {collect, &w1, false, false, 0, 0};
    CHECK(obj_parse(path, t.s, t.n, &opt, &whole, &err) == GLINT_OK);
    CHECK(load(path, &blocks, &w2, &err) == GLINT_OK);
    CHECK(whole.mesh.triangle_count > 200000 && whole.mesh.uv_count > 0 && whole.material_count == 4);
    CHECK(obj_same_model(&whole, &blocks, true));
    CHECK(w1.count == w2.count && w1.count > 0);
    for (int i = 0; i < w1.count && i < 16; i++) CHECK(same_string(w2.msg[i], w1.msg[i]));
    obj_model_free(&whole);
    obj_model_free(&blocks);

    // An error far into the file names the same line, whichever the block.
    static const char *const bad[] = {"f 1 2 999999999\n", "v 1 2 nan\n", "vn 1 2\n", "f 1 2\n", "vt 1.#INF 0\n",
                                      "f 1/1/1/1 2 3\n", "v 1 2 3 4 5 6 7 8\n"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        size_t cut = t.n / 2 + i * 100000;
        while (t.s[cut - 1] != '\n') cut++;
        text_buf b = {0};
        put_n(&b, t.s, cut);
        put(&b, bad[i]);
        put(&b, t.s + cut);
        CHECK(b.s && tmp_write(path, b.s, b.n));
        glint_error e1, e2;
        CHECK(b.s && obj_parse(path, b.s, b.n, NULL, &whole, &e1) == GLINT_ERR_INPUT);
        CHECK(load(path, &blocks, &w2, &e2) == GLINT_ERR_INPUT);
        CHECK(same_string(e2.message, e1.message));
        free(b.s);
    }
    free(t.s);

    // Lines at the limit: one of OBJ_MAX_LINE_BYTES bytes is read; one byte more is an error that gives the
    // line's whole length, whether the line ends, ends the file, or goes on for long after the limit.
    CHECK(write_long_line(path, OBJ_MAX_LINE_BYTES, "\nv 1 1 1\n"));
    CHECK(load(path, &blocks, &w2, &err) == GLINT_OK && blocks.mesh.position_count == 2);
    obj_model_free(&blocks);
    CHECK(write_long_line(path, OBJ_MAX_LINE_BYTES, ""));
    CHECK(load(path, &blocks, &w2, &err) == GLINT_OK && blocks.mesh.position_count == 1);
    obj_model_free(&blocks);
    static const struct { size_t length; const char *tail; const char *message; } too_long[] = {
        {OBJ_MAX_LINE_BYTES + 1, "\nv 1 1 1\n", "@/blocks.obj:2: line is 33554433 bytes long, expected at most 33554432 (32 MiB)"},
        {OBJ_MAX_LINE_BYTES + 1, "", "@/blocks.obj:2: line is 33554433 bytes long, expected at most 33554432 (32 MiB)"},
        {OBJ_MAX_LINE_BYTES + 3000000, "\r\n", "@/blocks.obj:2: line is 36554433 bytes long, expected at most 33554432 (32 MiB)"},
    };
    for (size_t i = 0; i < sizeof too_long / sizeof too_long[0]; i++) {
        CHECK(write_long_line(path, too_long[i].length, too_long[i].tail));
        CHECK(load(path, &blocks, &w2, &err) == GLINT_ERR_INPUT);
        CHECK(same_string(err.message, expand(too_long[i].message)));
    }
    remove(path);
}

// The plain reading of an OBJ file of triangles: strtof for every number, strtol for every index, smooth
// normals summed and normalised one loop at a time, the box over the triangles' corners. The fast reader
// must give these arrays bit for bit.
typedef struct plain_triangle {
    int32_t v[3], n[3], t[3], material;
} plain_triangle;

typedef struct plain_mesh {
    vec3 *p, *n;
    uv2 *t;
    plain_triangle *tri;
    size_t np, nn, nt, ntri;
    bounds3 box;
} plain_mesh;

static int32_t plain_index(const char *s, const char **end, size_t count) {
    char *e;
    long i = strtol(s, &e, 10);
    *end = e;
    return (int32_t)(i < 0 ? (long)count + i : i - 1);
}

static void plain_read(const char *text, plain_mesh *m, size_t cap) {
    memset(m, 0, sizeof *m);
    m->p = calloc(cap, sizeof *m->p);
    m->n = calloc(2 * cap, sizeof *m->n);
    m->t = calloc(cap, sizeof *m->t);
    m->tri = calloc(cap, sizeof *m->tri);
    m->box = bounds3_empty();
    if (!m->p || !m->n || !m->t || !m->tri) return;
    for (const char *s = text; *s;) {
        char *end;
        if (s[0] == 'v' && s[1] == ' ') {
            float x = strtof(s + 2, &end), y = strtof(end, &end), z = strtof(end, &end);
            m->p[m->np++] = v3(x, y, z);
        } else if (s[0] == 'v' && s[1] == 'n') {
            float x = strtof(s + 3, &end), y = strtof(end, &end), z = strtof(end, &end);
            m->n[m->nn++] = v3(x, y, z);
        } else if (s[0] == 'v' && s[1] == 't') {
            float u = strtof(s + 3, &end), v = strtof(end, &end);
            m->t[m->nt++] = (uv2){u, v};
        } else if (s[0] == 'f') {
            plain_triangle tr = {{0, 0, 0}, {-1, -1, -1}, {-1, -1, -1}, -1};
            const char *q = s + 1;
            for (int k = 0; k < 3; k++) {
                tr.v[k] = plain_index(q, &q, m->np);
                if (q[0] == '/' && q[1] != '/') tr.t[k] = plain_index(q + 1, &q, m->nt);
                if (q[0] == '/' && q[1] == '/') q++;
                if (q[0] == '/') tr.n[k] = plain_index(q + 1, &q, m->nn);
            }
            vec3 a = m->p[tr.v[0]], b = m->p[tr.v[1]], c = m->p[tr.v[2]];
            double u[3] = {(double)b.x - a.x, (double)b.y - a.y, (double)b.z - a.z};
            double w[3] = {(double)c.x - a.x, (double)c.y - a.y, (double)c.z - a.z};
            if (u[1] * w[2] - u[2] * w[1] != 0 || u[2] * w[0] - u[0] * w[2] != 0 || u[0] * w[1] - u[1] * w[0] != 0) {
                m->tri[m->ntri++] = tr;
                m->box = bounds3_union(m->box, tri_bounds(a, b, c));
            }
        }
        s = strchr(s, '\n');
        s = s ? s + 1 : "";
    }
    // Smooth normals as mesh_compute_normals defines them, one loop at a time.
    vec3 *acc = m->n + m->nn;
    for (size_t i = 0; i < m->np; i++) acc[i] = v3s(0.0f);
    for (size_t i = 0; i < m->ntri; i++) {
        const int32_t *v = m->tri[i].v;
        vec3 fn = v3_cross(v3_sub(m->p[v[1]], m->p[v[0]]), v3_sub(m->p[v[2]], m->p[v[0]]));
        if (v3_is_finite(fn))
            for (int k = 0; k < 3; k++) acc[v[k]] = v3_add(acc[v[k]], fn);
    }
    for (size_t i = 0; i < m->np; i++) {
        float len = v3_len(acc[i]);
        vec3 u = len > 0.0f && isfinite(len) ? v3_scale(acc[i], 1.0f / len) : v3s(0.0f);
        acc[i] = len > 0.0f && isfinite(len) && v3_is_finite(u) ? u : v3s(0.0f);
    }
    for (size_t i = 0; i < m->ntri; i++) {
        plain_triangle *tr = &m->tri[i];
        if (tr->n[0] < 0 || tr->n[1] < 0 || tr->n[2] < 0)
            for (int k = 0; k < 3; k++) tr->n[k] = (int32_t)m->nn + tr->v[k];
    }
    m->nn += m->np;
}

// A file of the shapes large meshes come in (exporters' %.6f, round-trip %.9g, exponents, integers, every
// face form, relative indices, CRLF) loads, smooth normals included, to exactly what the plain reader reads.
static void test_mesh_matches_plain_reader(void) {
    enum { VERTICES = 40000, TRIANGLES = 80000 };
    text_buf t = {0};
    rng r = rng_for_sample(5, 5, 0);
    char line[256];
    for (int i = 0; i < VERTICES; i++) {
        float x = rng_range(&r, -100, 100), y = rng_range(&r, -1, 1), z = rng_range(&r, 0, 1e-3f);
        switch (i % 5) {
        case 0: snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", (double)x, (double)y, (double)z); break;
        case 1: snprintf(line, sizeof line, "v %.9g %.9g %.9g\r\n", (double)x, (double)y, (double)z); break;
        case 2: snprintf(line, sizeof line, "v %.7e  %.3e\t%.12e\n", (double)x, (double)y, (double)z); break;
        case 3: snprintf(line, sizeof line, "v %d %.17g %.20f\n", (int)x, (double)y, (double)z); break;
        default: snprintf(line, sizeof line, "v %g %g %g 0.5 0.25 1\n", (double)x, (double)y, (double)z); break;
        }
        put(&t, line);
        if (i % 2 == 0) {
            snprintf(line, sizeof line, "vt %.6f %.6f\nvn %.6f %.6f %.6f\n", (double)rng_float(&r), (double)rng_float(&r),
                     (double)rng_range(&r, -1, 1), (double)rng_range(&r, -1, 1), (double)rng_range(&r, -1, 1));
            put(&t, line);
        }
    }
    int nvt = VERTICES / 2;
    for (int i = 0; i < TRIANGLES; i++) {
        int v[3], k[3];
        for (int j = 0; j < 3; j++) {
            // Three different corners: random points are then never in line, and every face is a triangle.
            do v[j] = 1 + (int)(rng_u32(&r) % VERTICES);
            while ((j > 0 && v[j] == v[0]) || (j > 1 && v[j] == v[1]));
            k[j] = 1 + (int)(rng_u32(&r) % (uint32_t)nvt);
        }
        switch (i % 5) {
        case 0: snprintf(line, sizeof line, "f %d %d %d\n", v[0], v[1], v[2]); break;
        case 1: snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\n", v[0], k[0], v[1], k[1], v[2], k[2]); break;
        case 2: snprintf(line, sizeof line, "f %d//%d %d//%d %d//%d\r\n", v[0], k[0], v[1], k[1], v[2], k[2]); break;
        case 3:
            snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", v[0], k[0], k[1], v[1], k[1], k[2], v[2], k[2], k[0]);
            break;
        default:
            snprintf(line, sizeof line, "f %d/-%d/%d %d %d\n", v[0] - VERTICES - 1, k[0], k[2], v[1], v[2] - VERTICES - 1);
            break;
        }
        put(&t, line);
    }
    put(&t, "f 1 1 2\n"); // no area: skipped
    CHECK(t.s && tmp_write(tmp_path("plain.obj"), t.s, t.n));
    if (!t.s) return;
    plain_mesh want;
    plain_read(t.s, &want, (size_t)TRIANGLES + 1);
    obj_model m;
    warnings w;
    glint_error err;
    CHECK(load(tmp_path("plain.obj"), &m, &w, &err) == GLINT_OK);
    CHECK(m.zero_area_faces == 1 && w.count == 1);
    CHECK(mesh_compute_normals(&m.mesh));
    const mesh *g = &m.mesh;
    CHECK(g->position_count == want.np && g->uv_count == want.nt && g->normal_count == want.nn &&
          g->triangle_count == want.ntri && want.ntri == TRIANGLES);
    if (g->position_count == want.np && g->uv_count == want.nt && g->normal_count == want.nn && g->triangle_count == want.ntri) {
        CHECK(memcmp(g->positions, want.p, want.np * sizeof *want.p) == 0);
        CHECK(memcmp(g->uvs, want.t, want.nt * sizeof *want.t) == 0);
        CHECK(memcmp(g->normals, want.n, want.nn * sizeof *want.n) == 0);
        bool same = true;
        for (size_t i = 0; i < want.ntri; i++) {
            const plain_triangle *p = &want.tri[i];
            mesh_corners n = mesh_triangle_normals(g, i), uv = mesh_triangle_uvs(g, i);
            same = same && g->triangles[i].material == p->material && memcmp(g->triangles[i].v, p->v, sizeof p->v) == 0;
            same = same && memcmp(n.i, p->n, sizeof p->n) == 0 && memcmp(uv.i, p->t, sizeof p->t) == 0;
        }
        CHECK(same);
        CHECK(memcmp(&g->bounds, &want.box, sizeof want.box) == 0);
    }
    obj_model_free(&m);
    free(want.p);
    free(want.n);
    free(want.t);
    free(want.tri);
    free(t.s);
}

int main(void) {
    if (!tmpdir_make("glint-test-obj")) return 1;
    test_cornell_original();
    test_spot();
    test_spider();
    test_bunny();
    test_edge_cases();
    test_malformed();
    test_warnings();
    // The fast paths decide nothing: the statement reader alone gives the same errors and warnings.
    statements_only = true;
    test_malformed();
    test_warnings();
    test_index_forms();
    test_blocks_match_whole_text();
    statements_only = false;
    test_mapping();
    test_texture_paths();
    test_unsupported_keys();
    test_index_forms();
    test_polygons();
    test_large_convex_face();
    test_limits();
    test_materials_in_obj();
    test_comments_and_blanks();
    test_numbers_match_strtof();
    test_blocks_match_whole_text();
    test_mesh_matches_plain_reader();
    // On several threads, in blocks of one line or less (16 bytes) and of many lines: the same models, warnings and
    // errors, on the same lines.
    for (int i = 0; i < 2; i++) {
        load_threads = 2 + i;
        load_block = i ? 4096 : 1;
        test_cornell_original();
        test_bunny();
        test_edge_cases();
        test_malformed();
        test_warnings();
        test_index_forms();
        test_polygons();
        test_comments_and_blanks();
        test_blocks_match_whole_text();
        test_mesh_matches_plain_reader();
    }
    load_threads = 0;
    load_block = 0;
    tmpdir_remove();
    return check_summary();
}
