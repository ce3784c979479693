// test_model_read.c — glTF and PLY files through io/model_read (assimp): what the records hold for the files of
// tests/data/models (made by its make.py), and that malformed ones are refused with a message naming the file.
// Skipped (every check passes vacuously, and says so) in a glint built without assimp.
#include "check.h"
#include "io/model_read.h"

#include <stdlib.h>
#include <string.h>

#define DIR GLINT_SOURCE_DIR "/tests/data/models/"

static size_t warnings;
static void count_warning(const char *message, void *user) {
    (void)message;
    (void)user;
    warnings++;
}

static bool load(const char *name, model_file *m, glint_error *err) {
    return model_read(name, count_warning, NULL, m, err) == GLINT_OK;
}

static void test_formats(void) {
    CHECK(model_format_of("a/b.PLY") == MODEL_FORMAT_PLY);
    CHECK(model_format_of("b.gltf") == MODEL_FORMAT_GLTF);
    CHECK(model_format_of("b.GLB") == MODEL_FORMAT_GLB);
    CHECK(model_format_of("b.obj") == MODEL_FORMAT_NONE);
    CHECK(model_format_of("dir.ply/b") == MODEL_FORMAT_NONE);
    CHECK(model_format_of("ply") == MODEL_FORMAT_NONE);
}

// One mesh, three placements: a node, a node's child (the parent's translation composed with its scale), a node.
static void test_reused(void) {
    model_file m;
    glint_error err;
    CHECK(load(DIR "reused.gltf", &m, &err));
    CHECK(m.mesh_count == 1 && m.placement_count == 3);
    if (m.mesh_count == 1 && m.placement_count == 3) {
        CHECK(m.meshes[0].geometry.triangle_count == 2 && m.meshes[0].geometry.position_count == 4);
        CHECK(m.placements[0].xf.m[0][3] == -1.5f);
        CHECK(m.placements[1].xf.m[0][3] == 1.5f && m.placements[1].xf.m[0][0] == 0.5f);
        CHECK(m.placements[2].xf.m[2][3] == -1.5f);
        const model_material *mat = &m.materials[m.meshes[0].material];
        CHECK(strcmp(mat->name, "clay") == 0 && !mat->is_default);
        CHECK(mat->base_color.x == 0.8f && mat->base_color.y == 0.3f && mat->metallic == 0.0f && mat->roughness == 1.0f);
    }
    CHECK(m.input_count == 1); // the .gltf alone: its buffer is a data: URI
    model_file_free(&m);
}

static void test_emissive(void) {
    model_file m;
    glint_error err;
    CHECK(load(DIR "emissive.gltf", &m, &err));
    if (m.material_count >= 1) {
        const model_material *mat = &m.materials[0];
        CHECK_NEAR(mat->emission.x, 4.0, 0.0);
        CHECK_NEAR(mat->emission.y, 2.0, 0.0);
        CHECK_NEAR(mat->emission.z, 1.0, 0.0);
        CHECK(mat->metallic == 0.25f && mat->roughness == 0.75f);
    }
    model_file_free(&m);
}

static void test_cameras_and_lights(void) {
    model_file m;
    glint_error err;
    CHECK(load(DIR "cameras.gltf", &m, &err));
    CHECK(m.camera_count == 2);
    if (m.camera_count == 2) {
        const model_camera *front = &m.cameras[0], *side = &m.cameras[1];
        CHECK(strcmp(front->name, "front") == 0 && strcmp(side->name, "side") == 0);
        CHECK_NEAR(front->yfov, 0.6, 1e-6);
        CHECK_NEAR(front->position.x, 0.25, 0.0);
        CHECK_NEAR(front->position.z, 4.0, 0.0);
        CHECK_NEAR(front->forward.z, -1.0, 0.0);
        CHECK_NEAR(front->up.y, 1.0, 0.0);
        // Turned a quarter about +y: looking along -x.
        CHECK_NEAR(side->yfov, 0.5, 1e-6);
        CHECK_NEAR(side->aspect, 1.5, 0.0);
        CHECK_NEAR(side->forward.x, -1.0, 1e-6);
        CHECK_NEAR(side->up.y, 1.0, 1e-6);
    }
    model_file_free(&m);
    CHECK(load(DIR "spot.gltf", &m, &err));
    CHECK(m.light_count == 1);
    if (m.light_count == 1) {
        const model_light *l = &m.lights[0];
        CHECK(l->kind == MODEL_LIGHT_SPOT);
        CHECK_NEAR(l->intensity.x, 8.0, 1e-5);
        CHECK_NEAR(l->intensity.y, 7.2, 1e-5);
        CHECK_NEAR(l->position.y, 2.0, 1e-6);
        CHECK_NEAR(l->direction.y, -1.0, 1e-6); // the node turns -z down
        CHECK_NEAR(l->inner_cone, 0.3, 1e-6);
        CHECK_NEAR(l->outer_cone, 0.6, 1e-6);
    }
    model_file_free(&m);
}

static void test_point_and_directional(void) {
    model_file m;
    glint_error err;
    CHECK(load(DIR "lights.gltf", &m, &err));
    CHECK(m.light_count == 2);
    for (size_t i = 0; i < m.light_count; i++) {
        const model_light *l = &m.lights[i];
        if (l->kind == MODEL_LIGHT_POINT) {
            CHECK(strcmp(l->name, "bulb") == 0);
            CHECK_NEAR(l->intensity.x, 2.0, 1e-6);
            CHECK_NEAR(l->intensity.y, 1.0, 1e-6);
            CHECK_NEAR(l->intensity.z, 0.5, 1e-6);
            CHECK(l->position.x == 1.0f && l->position.y == 2.0f && l->position.z == 3.0f);
        } else {
            CHECK(l->kind == MODEL_LIGHT_DIRECTIONAL && strcmp(l->name, "sun") == 0);
            CHECK_NEAR(l->intensity.y, 3.0, 1e-6); // white: glTF's default colour
            CHECK_NEAR(l->direction.y, -1.0, 1e-6); // travelling down: the node turns -z to -y
        }
    }
    model_file_free(&m);
}

// A PLY file has no materials: assimp's stand-in is marked.
static void test_ply(void) {
    model_file m;
    glint_error err;
    CHECK(load(DIR "quad.ply", &m, &err));
    CHECK(m.mesh_count == 1 && m.placement_count == 1 && m.material_count == 1);
    if (m.material_count == 1) CHECK(m.materials[0].is_default);
    if (m.mesh_count == 1) {
        const mesh *g = &m.meshes[0].geometry;
        CHECK(g->triangle_count == 2 && g->normals == NULL && g->uvs == NULL);
        // The file's triangles, as written: no joined or reordered vertices.
        CHECK(g->triangles[0].v[0] == 0 && g->triangles[0].v[1] == 2 && g->triangles[0].v[2] == 1);
    }
    model_file_free(&m);
}

// ---- binary PLY files read by glint itself (ply_read_fast) and by assimp: the same records, the same refusals ----

// Writes a binary little-endian PLY: `props` the vertex property lines, `floats` per vertex, then triangles (count
// byte `corners`: 3, or 4 for a quad made of the triangle's corners and its first again).
static void write_ply(const char *path, const char *props, int floats, const float *v, int nv, const int32_t *tri,
                      int nt, int corners) {
    FILE *f = fopen(path, "wb");
    if (!f) return;
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment made by test_model_read\nelement vertex %d\n%s"
               "element face %d\nproperty list uchar int vertex_indices\nend_header\n", nv, props, nt);
    fwrite(v, sizeof *v, (size_t)(nv * floats), f);
    for (int i = 0; i < nt; i++) {
        unsigned char c = (unsigned char)corners;
        fwrite(&c, 1, 1, f);
        fwrite(&tri[3 * i], 4, 3, f);
        if (corners == 4) fwrite(&tri[3 * i], 4, 1, f);
    }
    fclose(f);
}

static bool same_floats(const void *a, const void *b, size_t n) { return n == 0 || (a && b && memcmp(a, b, n) == 0); }

// Reads path both ways: both fail with the same message, or both give the same mesh and the same warning count.
static void check_both_ways(const char *path, bool expect_ok) {
    model_file a, b;
    glint_error ea, eb;
    size_t w0 = warnings;
    glint_status sa = model_read_ex(path, true, count_warning, NULL, &a, &ea);
    size_t wa = warnings - w0;
    glint_status sb = model_read_ex(path, false, count_warning, NULL, &b, &eb);
    size_t wb = warnings - w0 - wa;
    CHECK(sa == sb);
    CHECK((sa == GLINT_OK) == expect_ok);
    if (sa != GLINT_OK || sb != GLINT_OK) {
        bool same = sa != GLINT_OK && sb != GLINT_OK && strcmp(ea.message, eb.message) == 0;
        if (!same) fprintf(stderr, "%s:\n  fast:   %s\n  assimp: %s\n", path, sa ? ea.message : "ok", sb ? eb.message : "ok");
        CHECK(same);
        model_file_free(&a);
        model_file_free(&b);
        return;
    }
    CHECK(wa == wb);
    CHECK(a.mesh_count == 1 && b.mesh_count == 1 && a.placement_count == 1 && b.placement_count == 1);
    CHECK(a.material_count == 1 && a.materials[0].is_default && b.materials[0].is_default);
    CHECK(a.input_count == 1 && b.input_count == 1);
    if (a.mesh_count == 1 && b.mesh_count == 1) {
        const mesh *x = &a.meshes[0].geometry, *y = &b.meshes[0].geometry;
        CHECK(x->position_count == y->position_count && x->normal_count == y->normal_count &&
              x->uv_count == y->uv_count && x->triangle_count == y->triangle_count && x->smooth == y->smooth);
        if (x->position_count == y->position_count && x->triangle_count == y->triangle_count &&
            x->normal_count == y->normal_count && x->uv_count == y->uv_count) {
            CHECK(same_floats(x->positions, y->positions, x->position_count * sizeof *x->positions));
            CHECK(same_floats(x->normals, y->normals, x->normal_count * sizeof *x->normals));
            CHECK(same_floats(x->uvs, y->uvs, x->uv_count * sizeof *x->uvs));
            CHECK(same_floats(x->triangles, y->triangles, x->triangle_count * sizeof *x->triangles));
            CHECK((x->uv_corners == NULL) == (y->uv_corners == NULL));
            if (x->uv_corners && y->uv_corners)
                CHECK(same_floats(x->uv_corners, y->uv_corners, x->triangle_count * sizeof *x->uv_corners));
        }
    }
    model_file_free(&a);
    model_file_free(&b);
}

static void test_ply_fast_path(void) {
    const char *path = "test_model_read.tmp.ply";
    // A grid of 16 x 16 vertices with normals, a texture coordinate pair and a property glint skips.
    enum { N = 16 };
    float v[N * N * 9];
    int32_t tri[(N - 1) * (N - 1) * 6];
    int nt = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            float *p = &v[9 * (j * N + i)];
            p[0] = (float)i * 0.1f, p[1] = 0.01f * (float)((i * 7 + j * 3) % 5), p[2] = (float)j * 0.1f;
            p[3] = 0.0f, p[4] = 1.0f, p[5] = 0.0f;          // nx ny nz
            p[6] = 0.5f;                                    // confidence (skipped)
            p[7] = (float)i / (N - 1), p[8] = (float)j / (N - 1); // s t
        }
    for (int j = 0; j + 1 < N; j++)
        for (int i = 0; i + 1 < N; i++) {
            int32_t a = j * N + i, b = a + 1, c = a + N, d = c + 1;
            int32_t q[6] = {a, c, b, b, c, d};
            memcpy(&tri[3 * nt], q, sizeof q);
            nt += 2;
        }
    const char *full = "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                       "property float nz\nproperty float confidence\nproperty float s\nproperty float t\n";
    write_ply(path, full, 9, v, N * N, tri, nt, 3);
    check_both_ways(path, true);
    // Positions alone (every field but x y z named so that glint skips it).
    const char *plain = "property float x\nproperty float y\nproperty float z\nproperty float a\nproperty float b\n"
                        "property float c\nproperty float d\nproperty float e\nproperty float f\n";
    write_ply(path, plain, 9, v, N * N, tri, nt, 3);
    check_both_ways(path, true);
    // A triangle of zero area (skipped, one warning), an index out of range, a position that is not finite.
    int32_t keep = tri[2];
    tri[2] = tri[0];
    write_ply(path, plain, 9, v, N * N, tri, nt, 3);
    check_both_ways(path, true);
    tri[2] = N * N + 5;
    write_ply(path, plain, 9, v, N * N, tri, nt, 3);
    check_both_ways(path, false);
    tri[2] = -1;
    write_ply(path, plain, 9, v, N * N, tri, nt, 3);
    check_both_ways(path, false);
    tri[2] = keep;
    v[9 * 5 + 1] = INFINITY;
    write_ply(path, full, 9, v, N * N, tri, nt, 3);
    check_both_ways(path, false);
    v[9 * 5 + 1] = 0.0f;
    // Quads: not the fast layout's faces, read by assimp (the records are still both ways').
    write_ply(path, full, 9, v, N * N, tri, nt, 4);
    check_both_ways(path, true);
    remove(path);
}

static void test_refused(void) {
    static const struct {
        const char *file, *says;
    } bad[] = {
        {"index-out-of-range.gltf", "out-of-range"},
        {"infinite-vertex.gltf", "is not finite"},
        {"missing-bin.gltf", "cannot open \"" DIR "missing.bin\": No such file or directory"},
        {"recursive-nodes.gltf", "recursive"},
        {"cyclic-nodes.gltf", "recursive"},
        {"huge-count.gltf", "out of range"},
        {"deep-nodes.gltf", "nested deeper than 256"},
        {"huge-count.ply", "at most 2^31 - 1"},
        {"nan-vertex.ply", "is not finite"},
        {"index-out-of-range.ply", "vertex index 7 is out of range"},
        {"truncated.ply", "truncated, or a forged count"},
        {"does-not-exist.ply", "No such file"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char path[512];
        snprintf(path, sizeof path, DIR "%s", bad[i].file);
        model_file m;
        glint_error err;
        glint_status st = model_read(path, NULL, NULL, &m, &err);
        bool ok = st == GLINT_ERR_INPUT && strncmp(err.message, path, strlen(path)) == 0 && strstr(err.message, bad[i].says);
        if (!ok) fprintf(stderr, "%s: status %d, message: %s\n", bad[i].file, (int)st, st ? err.message : "");
        CHECK(ok);
        CHECK(m.mesh_count == 0 && m.meshes == NULL); // left empty
    }
}

int main(void) {
    test_formats();
    if (!model_read_available()) {
        model_file m;
        glint_error err;
        CHECK(model_read(DIR "quad.ply", NULL, NULL, &m, &err) == GLINT_ERR_INPUT && strstr(err.message, "without it"));
        printf("built without assimp: glTF and PLY files are refused\n");
        return check_summary();
    }
    test_reused();
    test_emissive();
    test_cameras_and_lights();
    test_point_and_directional();
    test_ply();
    test_ply_fast_path();
    test_refused();
    return check_summary();
}
