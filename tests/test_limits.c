// test_limits.c — running out of memory is a resource failure everywhere: OBJ, image and scene loads made to
// fail under a small address-space limit (setrlimit in a child process) give GLINT_ERR_RENDER and say so.
#include "check.h"
#include "test_util.h"
#include "glint.h"
#include "io/image_read.h"
#include "io/obj.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

/// Address space a child may use: far more than the test needs, far less than the files it reads.
#define CHILD_LIMIT ((rlim_t)192 << 20)

/// A load run in a child under CHILD_LIMIT: its status and message.
typedef struct outcome {
    int status;
    char message[1024];
} outcome;

typedef glint_status (*load_fn)(const char *path, glint_error *err);

#if !defined(GLINT_SANITIZE) // the helpers of the RLIMIT_AS runs, which sanitizer builds skip
static glint_status load_obj(const char *path, glint_error *err) {
    obj_model m;
    glint_status st = obj_load(path, NULL, &m, err);
    if (st == GLINT_OK) obj_model_free(&m);
    return st;
}

static glint_status load_image(const char *path, glint_error *err) {
    image_rgb img;
    glint_status st = image_read(path, IMAGE_DECODE_SRGB, &img, err);
    if (st == GLINT_OK) image_rgb_free(&img);
    return st;
}

static glint_status load_scene(const char *path, glint_error *err) {
    glint_scene *s = NULL;
    glint_status st = glint_scene_load(path, &s, err);
    glint_scene_free(s);
    return st;
}

// Runs load(path) in a child whose address space is limited; the outcome comes back through a pipe.
static outcome run_limited(load_fn load, const char *path) {
    outcome o = {-1, ""};
    int fd[2];
    if (pipe(fd) != 0) return o;
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        struct rlimit rl = {CHILD_LIMIT, CHILD_LIMIT};
        outcome r = {-1, ""};
        glint_error err = {{0}};
        if (setrlimit(RLIMIT_AS, &rl) == 0) r.status = (int)load(path, &err);
        snprintf(r.message, sizeof r.message, "%s", err.message);
        ssize_t w = write(fd[1], &r, sizeof r);
        _exit(w == (ssize_t)sizeof r ? 0 : 1);
    }
    close(fd[1]);
    if (pid > 0 && read(fd[0], &o, sizeof o) != (ssize_t)sizeof o) o.status = -1;
    close(fd[0]);
    if (pid > 0) waitpid(pid, NULL, 0);
    return o;
}

// A sparse file of `size` bytes that starts with `head`: reading it costs memory, not disk space.
static const char *sparse_file(const char *name, const char *head, size_t head_len, off_t size) {
    const char *path = tmp_path(name);
    FILE *f = fopen(path, "wb");
    bool ok = f && fwrite(head, 1, head_len, f) == head_len && ftruncate(fileno(f), size) == 0;
    if (f) fclose(f);
    CHECK(ok);
    return path;
}

static void expect(int line, outcome o, const char *want) {
    if (o.status == GLINT_ERR_RENDER && strcmp(o.message, want) == 0) {
        check_passed++;
        return;
    }
    check_failed++;
    fprintf(stderr, "%s:%d: status %d (want %d)\n  got:  %s\n  want: %s\n", __FILE__, line, o.status,
            (int)GLINT_ERR_RENDER, o.message, want);
}

// As expect(), for a message "<head><line number><tail>": where memory runs out depends on the C library.
static void expect_line(int line, outcome o, const char *head, const char *tail) {
    size_t h = strlen(head), d = 0;
    bool ok = o.status == GLINT_ERR_RENDER && strncmp(o.message, head, h) == 0;
    while (ok && o.message[h + d] >= '0' && o.message[h + d] <= '9') d++;
    if (ok && d > 0 && strcmp(o.message + h + d, tail) == 0) {
        check_passed++;
        return;
    }
    check_failed++;
    fprintf(stderr, "%s:%d: status %d (want %d)\n  got:  %s\n  want: %sLINE%s\n", __FILE__, line, o.status,
            (int)GLINT_ERR_RENDER, o.message, head, tail);
}

// An OBJ file of one triangle's corners and normal and `faces` lines "f 1//1 2//1 3//1" (a multiple of 4): 17
// bytes of text and 28 of mesh each (the triangle's 16, its normal indices' 12).
static const char *many_faces_file(const char *name, size_t faces) {
    const char *path = tmp_path(name);
    FILE *f = fopen(path, "wb");
    bool ok = f && fputs("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n", f) >= 0;
    static const char lines[] = "f 1//1 2//1 3//1\nf 1//1 2//1 3//1\nf 1//1 2//1 3//1\nf 1//1 2//1 3//1\n";
    for (size_t i = 0; ok && i < faces / 4; i++) ok = fwrite(lines, 1, sizeof lines - 1, f) == sizeof lines - 1;
    if (f) ok = fclose(f) == 0 && ok;
    CHECK(ok);
    return path;
}

#endif

int main(void) {
#if defined(GLINT_SANITIZE)
    // AddressSanitizer reserves terabytes of address space for its shadow memory: RLIMIT_AS cannot be used.
    puts("skipped: built with sanitizers (GLINT_SANITIZE), whose shadow memory defeats RLIMIT_AS");
    return 0;
#else
    if (!tmpdir_make("glint-test-limits")) return 1;
    char want[1200], scene[1400];
    // An 85 MB OBJ file (read a block at a time) whose 5 million triangles would take 140 MB: the arrays of
    // triangles and normal indices cannot both grow that far (with glibc, they stop doubling past 2^22
    // triangles, on line 4194309).
    const char *obj = many_faces_file("big.obj", 5000000);
    snprintf(want, sizeof want, "%s:", obj);
    expect_line(__LINE__, run_limited(load_obj, obj), want, ": out of memory");
    // A 200 MiB image (within the file size limit): its buffer cannot grow that far.
    const char *png = sparse_file("big.png", "\x89PNG\r\n\x1a\n", 8, (off_t)200 << 20);
    snprintf(want, sizeof want, "%s: out of memory while reading", png);
    expect(__LINE__, run_limited(load_image, png), want);
    // Through a scene file: the reader's message follows the scene's position, and the status stays.
    const char *json = tmp_path("s.json");
    snprintf(scene, sizeof scene, "{\"objects\": [{\"type\": \"mesh\", \"file\": \"big.obj\"}]}");
    CHECK(tmp_write(json, scene, strlen(scene)));
    snprintf(want, sizeof want, "%s:1:39: mesh file \"big.obj\" (%s): %s:", json, obj, obj);
    expect_line(__LINE__, run_limited(load_scene, json), want, ": out of memory");
    snprintf(scene, sizeof scene, "{\"textures\": {\"t\": {\"type\": \"image\", \"file\": \"big.png\"}}}");
    CHECK(tmp_write(json, scene, strlen(scene)));
    snprintf(want, sizeof want, "%s:1:46: image file \"big.png\" (%s): out of memory while reading", json, png);
    expect(__LINE__, run_limited(load_scene, json), want);
    tmpdir_remove();
    return check_summary();
#endif
}
