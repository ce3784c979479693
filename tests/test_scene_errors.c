// test_scene_errors.c — a table of malformed scenes, each with the exact message and status expected.
#include "check.h"
#include "glint.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_error_cases.h"

static void check_message(int line, glint_status status, const glint_scene *scene, const char *got, const char *want) {
    if (status == GLINT_ERR_INPUT && scene == NULL && strcmp(got, want) == 0) {
        check_passed++;
        return;
    }
    check_failed++;
    fprintf(stderr, "%s:%d: status %d (want %d), scene %s\n  got:  %s\n  want: %s\n", __FILE__, line, (int)status,
            (int)GLINT_ERR_INPUT, scene ? "returned" : "NULL", got, want);
}

static void run_table(void) {
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_scene *c = &cases[i];
        glint_scene *scene = NULL;
        glint_error err = {{0}};
        size_t len = c->len ? c->len : strlen(c->text);
        glint_status st = glint_scene_parse("bad.json", c->text, len, &scene, &err);
        check_message(c->line, st, scene, err.message, c->message);
        glint_scene_free(scene);
    }
}

// Nesting bombs fail at the first bracket past the limit, without deep recursion anywhere.
static void test_deep_nesting(void) {
    size_t n = 100000;
    char *text = malloc(n + 8);
    if (!text) return;
    memcpy(text, "{\"a\": ", 6);
    memset(text + 6, '[', n);
    glint_scene *scene = NULL;
    glint_error err;
    glint_status st = glint_scene_parse("deep.json", text, n + 6, &scene, &err);
    check_message(__LINE__, st, scene, err.message,
                  "deep.json:1:134: arrays and objects nested more than 128 levels deep");
    free(text);
}

// Size limits are checked before anything is parsed.
static void test_too_large(void) {
    glint_scene *scene = NULL;
    glint_error err;
    static const char text[] = "{}";
    glint_status st = glint_scene_parse("huge.json", text, (size_t)300 << 20, &scene, &err);
    check_message(__LINE__, st, scene, err.message,
                  "huge.json: the scene is 314572800 bytes; at most 268435456 bytes (256 MiB) are allowed");
}

// Files: a missing file, a directory, and a malformed file on disk give the reason or the position.
static void test_files(void) {
    glint_scene *scene = NULL;
    glint_error err;
    char want[1024];
    glint_status st = glint_scene_load("no/such/scene.json", &scene, &err);
    snprintf(want, sizeof want, "no/such/scene.json: cannot open: %s", strerror(ENOENT));
    check_message(__LINE__, st, scene, err.message, want);

    st = glint_scene_load(".", &scene, &err);
    snprintf(want, sizeof want, ".: cannot open: %s", strerror(EISDIR));
    check_message(__LINE__, st, scene, err.message, want);

    const char *path = "test_scene_errors.tmp.json";
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return;
    fputs("{\n  \"render\": {\"width\": 64, \"height\": 0}\n}\n", f);
    fclose(f);
    st = glint_scene_load(path, &scene, &err);
    check_message(__LINE__, st, scene, err.message,
                  "test_scene_errors.tmp.json:2:37: \"height\" must be an integer in [1, 16384], got 0");
    remove(path);
}

// Writes a small file for a test; false (and a failed check) when it cannot.
static bool write_file(const char *path, const char *text) {
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return false;
    fputs(text, f);
    return fclose(f) == 0;
}

// Parses text named `name` and checks the message starts with `prefix` (the rest is another reader's wording).
static void check_prefix(int line, const char *name, const char *text, const char *prefix) {
    glint_scene *scene = NULL;
    glint_error err = {{0}};
    glint_status st = glint_scene_parse(name, text, strlen(text), &scene, &err);
    if (st == GLINT_ERR_INPUT && scene == NULL && strncmp(err.message, prefix, strlen(prefix)) == 0) {
        check_passed++;
    } else {
        check_failed++;
        fprintf(stderr, "%s:%d: status %d\n  got:  %s\n  want: %s...\n", __FILE__, line, (int)st, err.message, prefix);
    }
    glint_scene_free(scene);
}

static void check_parse(int line, const char *name, const char *text, const char *want) {
    glint_scene *scene = NULL;
    glint_error err = {{0}};
    glint_status st = glint_scene_parse(name, text, strlen(text), &scene, &err);
    check_message(line, st, scene, err.message, want);
    glint_scene_free(scene);
}

// Mesh and image files: missing, directories, relative to the scene's directory, of the wrong kind, or broken.
static void test_referenced_files(void) {
    char want[1024];
    snprintf(want, sizeof want, "bad.json:1:39: mesh file \"nosuch.obj\": cannot open: %s", strerror(ENOENT));
    check_parse(__LINE__, "bad.json", "{\"objects\": [{\"type\": \"mesh\", \"file\": \"nosuch.obj\"}]}", want);
    snprintf(want, sizeof want, "bad.json:1:39: mesh file \".\": cannot open: %s", strerror(EISDIR));
    check_parse(__LINE__, "bad.json", "{\"objects\": [{\"type\": \"mesh\", \"file\": \".\"}]}", want);
    // Relative to the scene file's directory, which the message shows when it differs from what is written.
    snprintf(want, sizeof want, "sub/bad.json:1:39: mesh file \"x.obj\" (sub/x.obj): cannot open: %s",
             strerror(ENOENT));
    check_parse(__LINE__, "sub/bad.json", "{\"objects\": [{\"type\": \"mesh\", \"file\": \"x.obj\"}]}", want);
    snprintf(want, sizeof want, "sub/bad.json:1:39: mesh file \"/no/x.obj\": cannot open: %s", strerror(ENOENT));
    check_parse(__LINE__, "sub/bad.json", "{\"objects\": [{\"type\": \"mesh\", \"file\": \"/no/x.obj\"}]}", want);
    snprintf(want, sizeof want, "bad.json:1:46: image file \"nosuch.png\": cannot open: %s", strerror(ENOENT));
    check_parse(__LINE__, "bad.json", "{\"textures\": {\"t\": {\"type\": \"image\", \"file\": \"nosuch.png\"}}}", want);
    snprintf(want, sizeof want, "bad.json:1:46: image file \".\": cannot open: %s", strerror(EISDIR));
    check_parse(__LINE__, "bad.json", "{\"textures\": {\"t\": {\"type\": \"image\", \"file\": \".\"}}}", want);
    snprintf(want, sizeof want, "bad.json:1:80: image file \"no.jpg\": cannot open: %s", strerror(ENOENT));
    check_parse(__LINE__, "bad.json",
                "{\"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": {\"type\": \"image\", \"file\": "
                "\"no.jpg\"}}}}",
                want);
    // A long path keeps its end, where a misspelt file name is.
    snprintf(want, sizeof want,
             "bad.json:1:39: mesh file \"...scenes/meshes/stanford-bunny/stanfrd-bunny/stanfrd-bunny.obj\": cannot open: %s",
             strerror(ENOENT));
    check_parse(__LINE__, "bad.json",
                "{\"objects\": [{\"type\": \"mesh\", \"file\": "
                "\"../../../scenes/meshes/stanford-bunny/stanfrd-bunny/stanfrd-bunny.obj\"}]}",
                want);
    // Devices and other special files are refused before anything reads them.
    check_parse(__LINE__, "bad.json", "{\"objects\": [{\"type\": \"mesh\", \"file\": \"/dev/null\"}]}",
                "bad.json:1:39: mesh file \"/dev/null\": cannot open: not a regular file");

    const char *ply = "test_scene_errors.tmp.3ds", *obj = "test_scene_errors.tmp.obj",
               *png = "test_scene_errors.tmp.png", *mtl = "test_scene_errors.tmp.mtl",
               *obj2 = "test_scene_errors.tmp2.obj";
    if (write_file(ply, "3ds\n"))
        check_parse(__LINE__, "bad.json",
                    "{\"objects\": [{\"type\": \"mesh\", \"file\": \"test_scene_errors.tmp.3ds\"}]}",
                    "bad.json:1:39: mesh file \"test_scene_errors.tmp.3ds\": unsupported format; expected Wavefront "
                    "OBJ (.obj), glTF 2.0 (.gltf, .glb) or PLY (.ply)");
    // The OBJ reader's own message follows, with its file and line.
    if (write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"))
        check_prefix(__LINE__, "bad.json",
                     "{\"objects\": [{\"type\": \"mesh\", \"file\": \"test_scene_errors.tmp.obj\"}]}",
                     "bad.json:1:39: mesh file \"test_scene_errors.tmp.obj\": test_scene_errors.tmp.obj:4: ");
    // An image that does not decode: the image reader's reason, without its repeated path.
    if (write_file(png, "not an image\n")) {
        check_prefix(__LINE__, "bad.json",
                     "{\"textures\": {\"t\": {\"type\": \"image\", \"file\": \"test_scene_errors.tmp.png\"}}}",
                     "bad.json:1:46: image file \"test_scene_errors.tmp.png\": not a PNG or JPEG");
        // The same as an OBJ material's map_Kd: the message names the mesh and the material.
        if (write_file(mtl, "newmtl skin\nKd 1 1 1\nmap_Kd test_scene_errors.tmp.png\n") &&
            write_file(obj2, "mtllib test_scene_errors.tmp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl skin\nf 1 2 3\n"))
            check_prefix(__LINE__, "bad.json",
                         "{\"objects\": [{\"type\": \"mesh\", \"file\": \"test_scene_errors.tmp2.obj\"}]}",
                         "bad.json:1:39: mesh file \"test_scene_errors.tmp2.obj\": material \"skin\": image file "
                         "\"test_scene_errors.tmp.png\": not a PNG or JPEG");
    }
    remove(ply);
    remove(obj);
    remove(png);
    remove(mtl);
    remove(obj2);
}

int main(void) {
    run_table();
    test_referenced_files();
    test_deep_nesting();
    test_too_large();
    test_files();
    printf("%zu malformed scenes in the table\n", sizeof cases / sizeof cases[0]);
    return check_summary();
}
