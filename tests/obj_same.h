// obj_same.h — whether two loads of an OBJ file hold the same bytes (test_obj and fuzz_obj compare the fast
// paths of the reader with its statement reader by it).
#ifndef GLINT_TESTS_OBJ_SAME_H
#define GLINT_TESTS_OBJ_SAME_H

#include "io/obj.h"

#include <stdbool.h>
#include <string.h>

/// Every array, the box, the counts and the material slots' names (and, with `lines`, the lines that named them).
static inline bool obj_same_model(const obj_model *a, const obj_model *b, bool lines) {
    const mesh *x = &a->mesh, *y = &b->mesh;
    bool same = x->position_count == y->position_count && x->normal_count == y->normal_count &&
                x->uv_count == y->uv_count && x->triangle_count == y->triangle_count &&
                a->material_count == b->material_count && a->warning_count == b->warning_count &&
                a->zero_area_faces == b->zero_area_faces && memcmp(&x->bounds, &y->bounds, sizeof x->bounds) == 0;
    same = same && (!x->position_count || !memcmp(x->positions, y->positions, x->position_count * sizeof *x->positions));
    same = same && (!x->normal_count || !memcmp(x->normals, y->normals, x->normal_count * sizeof *x->normals));
    same = same && (!x->uv_count || !memcmp(x->uvs, y->uvs, x->uv_count * sizeof *x->uvs));
    same = same && (!x->triangle_count || !memcmp(x->triangles, y->triangles, x->triangle_count * sizeof *x->triangles));
    same = same && !x->normal_corners == !y->normal_corners && !x->uv_corners == !y->uv_corners;
    same = same && (!x->normal_corners ||
                    !memcmp(x->normal_corners, y->normal_corners, x->triangle_count * sizeof *x->normal_corners));
    same = same && (!x->uv_corners || !memcmp(x->uv_corners, y->uv_corners, x->triangle_count * sizeof *x->uv_corners));
    for (size_t i = 0; same && i < a->material_count; i++)
        same = strcmp(a->materials[i].name, b->materials[i].name) == 0 &&
               (!lines || a->materials[i].line == b->materials[i].line);
    return same;
}

#endif
