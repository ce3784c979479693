// scene_file_common.h — private to the scene-file reader (scene_file*.c): the reader's state, the helpers its
// sections share (scene_file_common.c) and the readers of its sections. Prefix sf_ ("scene file"). The entry
// points, scene_file_parse/_load (scene_file.c), are in scene.h. Calls run one way: scene_file.c -> the other
// scene_file_*.c -> scene_file_common.c.
//
// The reader embeds io/json_read's json_reader (positions, messages, typed values) and adds what only a
// scene has: the scene being built, the material and texture names, and the caches of files already read.
#ifndef GLINT_SCENE_FILE_COMMON_H
#define GLINT_SCENE_FILE_COMMON_H

#include "core/strmap.h"
#include "io/image_read.h"
#include "io/json_read.h"
#include "io/model_read.h"
#include "io/mtl.h"
#include "scene/scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/stat.h>

enum {
    SF_MAX_FILE_BYTES = SCENE_MAX_FILE_BYTES, ///< larger scene files are refused before parsing
    SF_MAX_ITEMS = 10000000,       ///< at most this many objects, materials and lights each
    SF_MAX_EXTENT = 1000000000,    ///< what renders lies within [-1e9, 1e9] on every axis (sf_check_extent)
    SF_LIST_NAMES = 10,            ///< material names listed in an "is not defined" message
    SF_MAX_WARNINGS = 100,         ///< warnings kept in the scene; the rest are counted in one more
    SF_MAX_NOISE_DEPTH = 32,       ///< octaves of turbulence (2^32 p is already far beyond any detail)
};


/// A name defined in "materials" or "textures" (or by a call of the scene API).
typedef struct sf_name {
    char *name;       ///< owned: a scene built call by call outlives each call's value
    uint32_t index;   ///< the scene material or texture
    uint32_t tok;     ///< where it is defined
} sf_name;

/// Name -> material or texture index, so that resolving references stays linear in the scene size.
typedef struct sf_names {
    strmap map;    ///< name -> position in list
    sf_name *list; ///< in definition order, for listing names in messages
    size_t count, cap;
} sf_names;

/// The identity of a file (device and inode): two spellings of one path are the same file.
typedef struct sf_file_id {
    dev_t dev;
    ino_t ino;
} sf_file_id;

/// A mesh file already loaded: placing it again adds an instance, not a copy.
typedef struct sf_mesh_entry {
    sf_file_id id;
    bool face_normals;   ///< the mesh's normals depend on this, so it is part of the key
    bool needs_fallback; ///< some faces have no material of their own (the grey fallback)
    bool warned;         ///< the missing-material warning was given
    uint32_t mesh;
} sf_mesh_entry;

/// A model file already imported: placing it again adds instances of the same scene meshes.
typedef struct sf_import_entry {
    sf_file_id id;
    uint32_t first_mesh; ///< the scene mesh of the model's mesh 0; the others follow in order
} sf_import_entry;

/// An image file already decoded into a texture.
typedef struct sf_image_entry {
    sf_file_id id;
    image_decode decode;   ///< the same file decoded otherwise is another texture
    texture_filter filter;
    uint32_t texture;
} sf_image_entry;

/// The reader of one scene file. r.status is GLINT_ERR_INPUT, or GLINT_ERR_RENDER when memory ran out.
/// Object types, in the order of scene_file_objects.c's object_types table, for counting what was read.
typedef enum sf_object_kind {
    SF_OBJECT_SPHERE,
    SF_OBJECT_QUAD,
    SF_OBJECT_BOX,
    SF_OBJECT_MESH,
    SF_OBJECT_CONSTANT_MEDIUM,
    SF_OBJECT_HOMOGENEOUS_MEDIUM,
    SF_OBJECT_IMPORT,
    SF_OBJECT_KINDS
} sf_object_kind;

typedef struct sf_loader {
    json_reader r; ///< the document, positions and the message of a failure
    glint_scene *scene;
    bool linear_images; ///< inline image textures default to "encoding": "linear" (data maps: normals, metallic...)
    sf_names materials;
    sf_names textures;
    sf_mesh_entry *meshes;
    size_t mesh_count, mesh_cap;
    sf_image_entry *images;
    size_t image_count, image_cap;
    sf_import_entry *imports; ///< model files imported ("import" objects), each loaded once
    size_t import_count, import_cap;
    const char *base;        ///< the path relative file names resolve against: the scene file's (its name)
    sf_names api_meshes;     ///< meshes a program added by name (glint_scene_add_mesh); none in a file
    long fallback_material;  ///< the grey Lambertian of faces without a material, once created; else -1
    int mesh_threads;        ///< threads that read a large mesh file (0: all online CPUs)
    size_t warnings_dropped; ///< warnings past SF_MAX_WARNINGS
    bool warning_oom;        ///< a warning could not be stored
    bool output_given;       ///< render.output was in the file (else the integrator's default applies)
    size_t object_counts[SF_OBJECT_KINDS]; ///< objects read, by type (for the warnings of sf_warn_unseen)
} sf_loader;

// scene_file_common.c: messages, names, files, the extent

/// "name: out of memory while reading the scene", status GLINT_ERR_RENDER; false.
bool sf_fail_oom(sf_loader *ld);
/// Keeps a warning in the scene (at most SF_MAX_WARNINGS; the rest are counted).
void sf_add_warning(sf_loader *ld, const char *message);
/// Keeps the warning "name:line:col: warning: message" for the byte at `offset`.
JR_PRINTF(3, 4) void sf_warn_at(sf_loader *ld, size_t offset, const char *fmt, ...);
/// The entry of a defined name, or NULL.
const sf_name *sf_names_find(const sf_names *t, const char *name);
/// Adds a name (copied) for `index`, defined at token tok; false when out of memory.
bool sf_names_add(sf_names *t, const char *name, uint32_t index, uint32_t tok);
/// Frees the table.
void sf_names_free(sf_names *t);
/// Checks `name` as a new name for `map` (1 to SCENE_MAX_NAME bytes, no control characters, unused), blaming the
/// byte at `offset` ("material name ... must be ..."); `shown` is the name as the file spells it, quoted.
bool sf_check_new_name(sf_loader *ld, const sf_names *map, size_t offset, const char *name, const char *shown,
                       const char *kind);
/// A loader for `scene` (name: messages and, as `base`, relative paths), its reader over nothing yet.
void sf_loader_init(sf_loader *ld, glint_scene *scene, const char *name, int threads, glint_error *err);
/// Frees what the loader holds but the scene.
void sf_loader_release(sf_loader *ld);
/// Without an "output" in the render settings, the integrator's encoding: linear in paper mode, else sRGB.
void sf_default_output(sf_loader *ld);
/// The scene's end: the default output encoding and the warnings about what will not be seen. False (message
/// written) when memory ran out.
bool sf_finish(sf_loader *ld);
/// Reads the "render" object into the scene's settings (the keys it has; the others keep their values).
bool sf_read_render(sf_loader *ld, jr_val v);
/// Reads the "camera" object.
bool sf_read_camera(sf_loader *ld, jr_val v);
/// "material "blu" is not defined (defined: red, green)", pointing at v; false.
bool sf_fail_undefined(sf_loader *ld, jr_val v, const sf_names *map, const char *kind);
/// " (resolved/path)" when the path opened differs from the one written, else "".
const char *sf_resolved_note(const char *written, const char *path, char *buf, size_t size);
/// Reads the required path `key` of o, resolves it against the scene file's directory (*path, malloc'd)
/// and checks that it names a regular file (*id); `kind` ("mesh", "image") names it in messages.
bool sf_read_file_path(sf_loader *ld, const jr_obj *o, const char *key, const char *kind, char **path,
                       sf_file_id *id, jr_val *where);

/// Checks that box b (world space) lies within SF_MAX_EXTENT on every axis, so that no squared distance,
/// ray-sphere discriminant or edge function of the intersection tests can overflow single precision (which
/// would make samples NaN); otherwise writes "<what> reaches <x> on the <axis> axis; ..." at `offset`.
bool sf_check_extent(sf_loader *ld, size_t offset, const char *what, bounds3 b);

/// Adds material m of a mesh or model file as "FILE:NAME" (file as the scene wrote it), blaming `where` when the
/// scene has too many; *index is its number.
bool sf_add_file_material(sf_loader *ld, size_t where, const char *file, const char *name, const material *m,
                          uint32_t *index);
/// The grey Lambertian of faces without a material (meshes from any file or array), created on first use; false
/// when out of memory.
bool sf_fallback_material(sf_loader *ld, uint32_t *index);

// scene_file_warnings.c: what a loaded scene will not show

/// Warns about what the loaded scene will not show: no light at all, and what paper mode drops.
void sf_warn_unseen(sf_loader *ld);

// scene_file_materials.c: textures, images, materials

/// The scene texture of image file `path` (id) decoded and filtered as asked, decoded on first use; `where` is
/// blamed for failures, and `prefix` (may be "") opens their message.
bool sf_load_image(sf_loader *ld, size_t where, const char *prefix, const char *written, const char *path,
                   sf_file_id id, image_decode decode, texture_filter filter, uint32_t *index);
/// The image texture keys' values, in order ("srgb", "linear"; "bilinear", "nearest").
extern const char *const sf_image_encodings[2], *const sf_image_filters[2];
/// Reads a texture object and adds it to the scene (named, or anonymous when name is NULL).
bool sf_read_texture(sf_loader *ld, jr_val v, const char *what, const char *name, uint32_t *index);
/// Reads a material object and adds it to the scene (named, or anonymous when name is NULL).
bool sf_read_material(sf_loader *ld, jr_val v, const char *what, const char *name, uint32_t *index);
/// The "material" of an object: a name defined in "materials", or an inline material object.
bool sf_read_material_ref(sf_loader *ld, const jr_obj *o, const char *owner, uint32_t *index);
/// The optional colour parameter `key` of o: a colour (into *color) or a texture, by name or inline (into *tex),
/// as material colours are read; a texture must stay within sp's upper bound.
bool sf_read_color_or_texture(sf_loader *ld, const jr_obj *o, const char *key, const jr_numspec *sp, vec3 *color,
                              int32_t *tex);

// scene_file_objects.c: transforms, shapes, lights

/// Reads the optional "transform" of o into *xf (object to world); *given is false without one.
bool sf_read_transform(sf_loader *ld, const jr_obj *o, transform *xf, bool *given);
/// Reads the optional "transform2" of o, the pose at time 1 of an object whose "transform" (xf) is its pose at
/// time 0, checks the motion between them (object_bounds swept over [0, 1] within the extent; `shape` names the
/// object in messages) and adds it to the scene: *motion_ref is the instance.motion value, 0 without one.
bool sf_read_motion(sf_loader *ld, const jr_obj *o, const transform *xf, bounds3 object_bounds, const char *shape,
                    uint32_t *motion_ref);
/// Reads element i of "objects" into the scene.
bool sf_read_object(sf_loader *ld, jr_val v, size_t i);
/// Reads element i of "lights" into the scene.
bool sf_read_light(sf_loader *ld, jr_val v, size_t i);

// scene_file_mesh.c: OBJ meshes placed by the scene

/// A "mesh" object: its OBJ file loaded once (materials mapped to scene materials), or a mesh a program added
/// ("mesh": its name), placed as an instance.
bool sf_read_mesh(sf_loader *ld, const jr_obj *o, const char *what);
/// The glint material of an MTL material's values (the policy: docs/scene-format.md, "Meshes").
material sf_mtl_material(const mtl_values *v);

// scene_file_import.c: glTF and PLY files (models)

/// Reads model file `path` (written as `file`; `kind`, "mesh" or "import", names it in messages) and records the
/// files it read as scene inputs.
bool sf_model_load(sf_loader *ld, jr_val file, const char *path, const char *kind, model_file *model);
/// Whether every fragment of the mesh is cut away (alphaMode MASK with baseColorFactor's alpha below the cutoff):
/// such meshes are not placed.
bool sf_model_fully_cut(const model_file *model, const model_mesh *placed);
/// Model material i as a new scene material named "FILE:NAME", with its textures.
bool sf_model_material(sf_loader *ld, jr_val file, const model_file *model, size_t i, uint32_t *index);
/// An "import" object: every node's meshes placed as instances (under the object's "transform"), the file's lights.
bool sf_read_import(sf_loader *ld, const jr_obj *o, const char *what);
/// A camera {"type": "import", "file", "name", "transform", "shutter"}: the file's perspective camera as a look-at one.
bool sf_read_import_camera(sf_loader *ld, const jr_obj *o, camera *c);

// scene_file_media.c: participating media

/// A "constant_medium" object (book 2's: boundary, density, albedo, g).
bool sf_read_constant_medium(sf_loader *ld, const jr_obj *o, const char *what);
/// A "homogeneous_medium" object (boundary, sigma_a, sigma_s, g).
bool sf_read_homogeneous_medium(sf_loader *ld, const jr_obj *o, const char *what);

#endif
