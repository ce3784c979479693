// model_file.h — what a model file (glTF 2.0, PLY) is read into: plain glint records of triangle meshes, the nodes
// that place them, glTF metallic-roughness materials, images, punctual lights, cameras and the files read; the
// limits every reader checks, and the helpers the readers share (model_read.c through assimp, ply_fast.c for the
// simplest binary PLY files).
#ifndef GLINT_MODEL_FILE_H
#define GLINT_MODEL_FILE_H

#include "core/status.h"
#include "geometry/mesh.h"
#include "geometry/transform.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/stat.h>

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
/// Frees what a reader returned and leaves *m empty.
void model_file_free(model_file *m);
/// Records the file of status *st (read at `path`) among m's inputs, once; false when memory runs out.
bool model_file_add_input(model_file *m, const struct stat *st, const char *path);
/// Hands warn (when not NULL) the message "path: warning: " followed by the formatted text.
void model_file_warn(model_warning_fn warn, void *user, const char *path, const char *fmt, va_list ap)
    __attribute__((format(printf, 4, 0)));

#endif
