// fuzz_obj.c — libFuzzer target for the OBJ and MTL readers: any bytes must give a mesh or a message, never
// a crash, a leak, a hang or undefined behaviour, and the same one with the fast paths as without them.
// Whatever loads is then used as a renderer would use it. Read from a file, the bytes give the same on several
// threads (the parallel reader, in small blocks) as on one.
// Build with -DGLINT_FUZZ=ON and CC=clang; run: build/tests/fuzz_obj -dict=tests/fuzz/obj.dict NEWDIR tests/fuzz/corpus_obj
#define _GNU_SOURCE // memfd_create
#include "geometry/mesh.h"
#include "io/mtl.h"
#include "io/obj.h"
#include "../obj_same.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

// A failure has a status, a non-empty terminated message and an empty model.
static void check_failure(const glint_error *err) {
    if (memchr(err->message, '\0', sizeof err->message) == NULL || err->message[0] == '\0') __builtin_trap();
}

// The bytes as a file (in memory) read by obj_load on one thread and on three in blocks of 16 to 79 bytes: the
// same status, message and model.
static void check_threads(const uint8_t *data, size_t size) {
    int fd = memfd_create("fuzz.obj", 0);
    if (fd < 0) return;
    char path[64];
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
    if (write(fd, data, size) == (ssize_t)size) {
        obj_options one = {NULL, NULL, true, false, 1, 0}, three = {NULL, NULL, true, false, 3, 16 + size % 64};
        obj_model a, b;
        glint_error ea, eb;
        glint_status sa = obj_load(path, &one, &a, &ea), sb = obj_load(path, &three, &b, &eb);
        if (sa != sb || (sa != GLINT_OK && strcmp(ea.message, eb.message) != 0)) __builtin_trap();
        if (sa == GLINT_OK) {
            if (!obj_same_model(&a, &b, true)) __builtin_trap();
            obj_model_free(&a);
            obj_model_free(&b);
        }
    }
    close(fd);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    check_threads(data, size);
    // No files: a fuzzed `mtllib /dev/zero` must not be read.
    obj_options opt = {NULL, NULL, true, false, 0, 0}, statements = {NULL, NULL, true, true, 0, 0};
    obj_model m, slow;
    glint_error err, slow_err;
    // The fast paths decide nothing: reading every line as a statement gives the same model or message.
    glint_status st = obj_parse("fuzz.obj", (const char *)data, size, &opt, &m, &err);
    glint_status slow_st = obj_parse("fuzz.obj", (const char *)data, size, &statements, &slow, &slow_err);
    if (st != slow_st || (st != GLINT_OK && strcmp(err.message, slow_err.message) != 0)) __builtin_trap();
    if (st == GLINT_OK) {
        if (!obj_same_model(&m, &slow, false)) __builtin_trap();
        obj_model_free(&slow);
        // The box grown triangle by triangle is mesh_compute_bounds's, bit for bit.
        mesh copy = m.mesh;
        bounds3 b = mesh_compute_bounds(&copy);
        if (memcmp(&b, &m.mesh.bounds, sizeof b) != 0) __builtin_trap();
    }
    if (st == GLINT_OK) {
        const mesh *me = &m.mesh;
        for (size_t i = 0; i < me->triangle_count; i++) {
            const mesh_triangle *t = &me->triangles[i];
            mesh_corners n = mesh_triangle_normals(me, i), uv = mesh_triangle_uvs(me, i);
            for (int k = 0; k < 3; k++)
                if (t->v[k] < 0 || (size_t)t->v[k] >= me->position_count || n.i[k] >= (int32_t)me->normal_count ||
                    uv.i[k] >= (int32_t)me->uv_count)
                    __builtin_trap();
            if (t->material < -1 || t->material >= (int32_t)m.material_count) __builtin_trap();
            // Shade the centroid and fire a ray at it, as the renderer would.
            tri_hit h = {1.0f, 1.0f / 3, 1.0f / 3, 1.0f / 3};
            mesh_shading s = mesh_shade(me, i, &h);
            (void)s;
            vec3 p0, p1, p2;
            mesh_triangle_positions(me, i, &p0, &p1, &p2);
            vec3 c = v3_scale(v3_add(p0, v3_add(p1, p2)), 1.0f / 3);
            ray r = {v3_add(c, v3(0.5f, 0.25f, 1)), v3(-0.5f, -0.25f, -1), 0, INFINITY, 0.0f};
            tri_ray tr = tri_ray_make(&r);
            tri_hit hit;
            (void)mesh_intersect_triangle(me, i, &tr, r.tmin, r.tmax, &hit);
        }
        mesh_compute_normals(&m.mesh);
        obj_model_free(&m);
    } else {
        check_failure(&err);
        if (m.mesh.positions || m.mesh.triangles || m.materials) __builtin_trap();
    }
    // The same bytes as a material library.
    mtl_options mopt = {NULL, NULL, true};
    mtl_library lib;
    if (mtl_parse("fuzz.mtl", (const char *)data, size, &mopt, &lib, &err) == GLINT_OK) {
        // The unsupported keys are named, and the line of the first is known when there are any.
        for (unsigned k = 0; k < 32; k++)
            if ((lib.unsupported >> k & 1) && !mtl_unsupported_key_name(k)) __builtin_trap();
        if (!lib.unsupported != !lib.unsupported_line) __builtin_trap();
        mtl_library_free(&lib);
    } else {
        check_failure(&err);
        if (lib.records || lib.count) __builtin_trap();
    }
    return 0;
}
