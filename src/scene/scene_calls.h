// scene_calls.h — a scene built, or extended, call by call (the public glint_scene_add_* calls): each call hands
// the scene file's reader one value — the render settings, the camera, a texture, a material, an object, a light —
// so that a scene made in code is checked by the same code, and fails with the same messages, as a scene file.
// Only triangle arrays and pixel arrays, which a file names by path instead, have readers of their own here.
#ifndef GLINT_SCENE_CALLS_H
#define GLINT_SCENE_CALLS_H

#include "core/status.h"
#include "scene/scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// The part of a scene one value describes: a key of the scene file's top level.
typedef enum scene_call_part {
    SCENE_CALL_RENDER,   ///< the "render" object: the keys it has replace the scene's values
    SCENE_CALL_CAMERA,   ///< the "camera" object: replaces the camera
    SCENE_CALL_TEXTURE,  ///< one named entry of "textures"
    SCENE_CALL_MATERIAL, ///< one named entry of "materials"
    SCENE_CALL_OBJECT,   ///< one element of "objects"
    SCENE_CALL_LIGHT     ///< one element of "lights"
} scene_call_part;

/// Reads one value, JSON text of `length` bytes, as `part` of scene s; `name` names a texture or material (and
/// only those). Messages open with `call` ("glint_scene_add_object: object 2 (sphere): \"radius\" must be ...",
/// the scene file's words after its "file:line:col: "). A call that fails leaves the scene as it was.
glint_status scene_call_read(glint_scene *s, scene_call_part part, const char *call, const char *name,
                             const char *json, size_t length, glint_error *err);

/// A triangle mesh in a program's arrays (glint_mesh_data, field for field): copied by scene_call_add_mesh.
typedef struct scene_mesh_arrays {
    size_t vertex_count;
    const float *positions; ///< 3 a vertex
    const float *normals;   ///< 3 a vertex, or NULL: smooth normals computed as for an OBJ file without any
    const float *uvs;       ///< 2 a vertex, or NULL
    size_t triangle_count;
    const uint32_t *indices;        ///< 3 a triangle, each < vertex_count
    const uint32_t *face_materials; ///< a triangle's slot in materials, or NULL: the placing object's material
    const char *const *materials;   ///< names of materials defined before
    size_t material_count;
    bool flat; ///< shade every triangle with its geometric normal (normals are then not allowed)
} scene_mesh_arrays;

/// Adds a mesh under `name`, which "mesh" objects place ({"type": "mesh", "mesh": name, "transform": ...}).
glint_status scene_call_add_mesh(glint_scene *s, const char *call, const char *name, const scene_mesh_arrays *a,
                                 glint_error *err);

/// Pixels in a program's array (glint_pixels, field for field), row 0 at the top.
typedef struct scene_pixels {
    int width, height, channels; ///< channels: 1 (grey), 3 (RGB) or 4 (RGBA: alpha, linear in [0, 1], for masks)
    const float *values;         ///< linear values, or NULL
    const uint8_t *bytes;        ///< 8-bit values, decoded as the options' "encoding" says, or NULL
} scene_pixels;

/// Adds a named image texture from pixels; `options` (JSON text of an object, may be NULL) holds the image
/// texture's "encoding" and "filter".
glint_status scene_call_add_image(glint_scene *s, const char *call, const char *name, const scene_pixels *px,
                                  const char *options, size_t length, glint_error *err);

#endif
