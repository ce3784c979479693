// model_read.h — glTF 2.0 (.gltf with its .bin and images, .glb) and PLY (ASCII and binary) files read through the
// Open Asset Import Library (assimp, Debian's libassimp-dev, its C API) into plain glint records: triangle meshes,
// the nodes that place them, glTF metallic-roughness materials, embedded images, punctual lights and cameras.
//
// assimp parses; glint checks what it hands back before anything is built from it (model_read.c): every file is
// opened by glint (a regular file, checked on its descriptor: a FIFO or a device never hangs the load, a missing
// .bin names itself) and is at most MODEL_MAX_FILE_BYTES; every index is in range (assimp drops faces with
// out-of-range indices with a warning: glint refuses the file, as it refuses an OBJ index out of range); every
// position, normal, texture coordinate and node transform is finite; counts stay within the MODEL_MAX_* limits.
// Faces of zero area and points and lines are skipped, with one warning each per file (as the OBJ reader does).
//
// assimp's post-processing is kept to triangulating polygons (PLY): no joined, generated or smoothed vertices,
// so the file's vertices and normals are the mesh's. assimp stores glTF texture coordinates with v up (it flips
// glTF's top-left origin), which is glint's convention (v = 1 is the image's top row).
//
// The simplest binary PLY files (little-endian, float vertex properties, triangles with a uchar count and 32-bit
// indices: what scanners and exporters write for large meshes) are read by glint itself (ply_read_fast), to the same
// records with the same checks and messages as through assimp (test_model_read compares the two): assimp's generic
// PLY tables took twice the time glint's OBJ reader takes for the same mesh. Every other PLY goes through assimp.
//
// Built without assimp (GLINT_HAVE_ASSIMP undefined), model_read refuses every file with a message that says so.
#ifndef GLINT_MODEL_READ_H
#define GLINT_MODEL_READ_H

#include "core/status.h"
#include "geometry/mesh.h"
#include "geometry/transform.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum {
    MODEL_MAX_FILE_BYTES = 1 << 30,   ///< each file a model reads (the model, its .bin buffers): 1 GiB
    MODEL_MAX_NODE_DEPTH = 256,       ///< nesting of the node hierarchy
    MODEL_MAX_PLACEMENTS = 1 << 20,   ///< (node, mesh) pairs: instances of an import
    MODEL_MAX_ITEMS = 1 << 16,        ///< materials, images, lights, cameras each
};

/// The file formats model_read takes, by file name extension.
typedef enum model_format { MODEL_FORMAT_NONE, MODEL_FORMAT_PLY, MODEL_FORMAT_GLTF, MODEL_FORMAT_GLB } model_format;

/// alphaMode of a glTF material.
typedef enum model_alpha_mode { MODEL_ALPHA_OPAQUE, MODEL_ALPHA_MASK, MODEL_ALPHA_BLEND } model_alpha_mode;

/// An image a material uses: a file beside the model, or bytes embedded in it (GLB buffer, data URI).
typedef struct model_image {
    char *path;          ///< a file, as a path usable from the current directory; NULL when embedded
    unsigned char *data; ///< embedded bytes (PNG or JPEG), owned; NULL for a file
    size_t size;
    char *name;          ///< for messages: the path as the model wrote it, or "image N (embedded)"
} model_image;

/// A glTF metallic-roughness material (appendix B of the specification), with its texture images (-1: none).
typedef struct model_material {
    char *name;
    bool is_default;        ///< assimp's stand-in for faces without a material (every PLY face): no material at all
    vec3 base_color;        ///< baseColorFactor's RGB (linear)
    float alpha;            ///< baseColorFactor's A
    float metallic, roughness, ior, transmission;
    vec3 emission;          ///< emissiveFactor times KHR_materials_emissive_strength (read by glint: assimp 5.2 does not)
    int32_t base_color_image, metallic_roughness_image, normal_image, emissive_image, transmission_image;
    float normal_scale;
    model_alpha_mode alpha_mode;
    float alpha_cutoff;     ///< MASK: fragments with alpha below it are cut away (0.5 by default)
    bool double_sided;
} model_material;

/// One mesh of the file (a glTF primitive): triangles with material slot -1 (the mesh's material).
typedef struct model_mesh {
    mesh geometry;     ///< bounds computed; normals only where the file has them
    uint32_t material; ///< index into model_file.materials
} model_mesh;

/// A mesh placed by a node: the node's transform composed with its ancestors' (object to model space).
typedef struct model_placement {
    uint32_t mesh;
    mat4 xf;
} model_placement;

typedef enum model_light_kind { MODEL_LIGHT_POINT, MODEL_LIGHT_DIRECTIONAL, MODEL_LIGHT_SPOT } model_light_kind;

/// A KHR_lights_punctual light, placed by its node (model space).
typedef struct model_light {
    model_light_kind kind;
    char *name;
    vec3 intensity;                 ///< colour times intensity (candela for point and spot, lux for directional)
    vec3 position;                  ///< point, spot
    vec3 direction;                 ///< directional, spot: unit, the way the light travels
    float inner_cone, outer_cone;   ///< spot: angles from the axis, radians
} model_light;

/// A perspective camera, placed by its node (model space).
typedef struct model_camera {
    char *name;
    vec3 position, forward, up; ///< forward and up: unit, perpendicular
    float yfov;                 ///< vertical field of view, radians
    float aspect;               ///< width / height the file gives, 0 when it gives none
} model_camera;

/// A file a model read, by identity: the model itself and every file it referenced.
typedef struct model_input {
    uint64_t dev, ino;
    char *path;
} model_input;

/// A loaded model. Free with model_file_free.
typedef struct model_file {
    model_mesh *meshes;
    size_t mesh_count;
    model_placement *placements; ///< in node order, depth first
    size_t placement_count;
    model_material *materials;
    size_t material_count;
    model_image *images;
    size_t image_count;
    model_light *lights;
    size_t light_count;
    model_camera *cameras;
    size_t camera_count;
    model_input *inputs;
    size_t input_count;
} model_file;

/// Receives each warning, "file: warning: what happened; what is done instead".
typedef void (*model_warning_fn)(const char *message, void *user);

/// The format of `path` by its extension (.ply, .gltf, .glb in any case), or MODEL_FORMAT_NONE.
model_format model_format_of(const char *path);
/// Whether this glint was built with assimp.
bool model_read_available(void);
/// Reads a model file. On failure returns GLINT_ERR_INPUT (GLINT_ERR_RENDER when memory runs out) with a message
/// that starts with the file's path, and *out is empty.
glint_status model_read(const char *path, model_warning_fn warn, void *user, model_file *out, glint_error *err);
/// model_read, with (fast_ply) or without glint's own reading of the simplest binary PLY files (little-endian float
/// vertices, triangles only: ply_read_fast in model_read.c; every other file goes through assimp). The tests read a
/// file both ways and compare.
glint_status model_read_ex(const char *path, bool fast_ply, model_warning_fn warn, void *user, model_file *out,
                           glint_error *err);
/// Frees what model_read returned and leaves *m empty.
void model_file_free(model_file *m);

#endif
