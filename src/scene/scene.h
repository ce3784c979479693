// scene.h — the scene: plain data, what the scene file said after the command line's overrides. What a render
// builds from it (acceleration structure, light index, prepared camera) lives in the render frame, not here.
#ifndef GLINT_SCENE_H
#define GLINT_SCENE_H

#include "core/status.h"
#include "accel/accel.h"
#include "core/vec.h"
#include "camera/camera.h"
#include "film/film.h"
#include "material/material.h"
#include "light/envmap.h"
#include "light/light.h"
#include "geometry/geometry.h"
#include "geometry/instance.h"
#include "geometry/mesh.h"
#include "geometry/motion.h"
#include "geometry/sphere.h"
#include "geometry/transform.h"
#include "geometry/quad.h"
#include "geometry/triangle.h"
#include "material/texture.h"
#include "medium/medium.h"

#include <stddef.h>
#include <stdint.h>

typedef enum integrator_kind { INTEGRATOR_WHITTED, INTEGRATOR_PATH } integrator_kind;
typedef enum whitted_mode { WHITTED_PAPER, WHITTED_COLOR } whitted_mode;
enum { INTEGRATOR_KIND_COUNT = INTEGRATOR_PATH + 1, WHITTED_MODE_COUNT = WHITTED_COLOR + 1 };
/// Their names, in order ("whitted", "path"; "paper", "color"), as scene files and checkpoints say them.
extern const char *const integrator_kind_names[INTEGRATOR_KIND_COUNT];
extern const char *const whitted_mode_names[WHITTED_MODE_COUNT];
/// Where the path tracer's samples take their random numbers (core/rng.h): the Owen-scrambled Sobol' sampler
/// (core/sobol.h) or independent PCG32 numbers. The Whitted integrators always draw independent ones.
typedef enum sampler_kind { SAMPLER_SOBOL, SAMPLER_INDEPENDENT } sampler_kind;
enum { SAMPLER_KIND_COUNT = SAMPLER_INDEPENDENT + 1 };
/// Their names, in order ("sobol", "independent"): the scene's "sampler", --sampler, checkpoints.
extern const char *const sampler_kind_names[SAMPLER_KIND_COUNT];
typedef enum background_kind { BACKGROUND_CONSTANT, BACKGROUND_SKY, BACKGROUND_ENVMAP } background_kind;

/// The "render" object of a scene file.
typedef struct render_settings {
    int width, height, spp, max_depth;
    uint64_t seed;
    integrator_kind integrator;
    whitted_mode whitted_mode;
    background_kind background;
    vec3 background_color;        ///< constant background radiance
    vec3 sky_horizon, sky_zenith; ///< sky: lerp(horizon, zenith, 0.5 * (dir.y + 1))
    output_transform transform;
    accel_kind accel;
    bool no_presplit; ///< "presplit": false: long, slanted triangles keep whole boxes (accel_build_options)
    bool no_spatial;  ///< "spatial_splits": false: the BVH splits between whole primitives only (accel_build_options)
    sampler_kind sampler; ///< the path tracer's random numbers
    float noise_threshold; ///< adaptive sampling: a pixel below this estimated relative error stops (0: off)
} render_settings;

/// Hard limits on sizes, so that a scene file cannot ask for absurd amounts of memory or time.
enum {
    SCENE_MAX_DIMENSION = 16384,
    SCENE_MAX_FILE_BYTES = 256 << 20, ///< larger scene texts are refused (GLINT_MAX_SCENE_BYTES, the public name)
    SCENE_MAX_SPP = 1000000,
    SCENE_MAX_DEPTH = 10000,
    SCENE_MAX_NAME = 128,
    SCENE_MAX_NOISE_THRESHOLD = 1000, ///< "noise_threshold", --noise-threshold: at most this
};

/// A mesh loaded from a file, shared by every instance that places it.
typedef struct scene_mesh {
    mesh geometry;
    uint32_t *slot_material; ///< mesh material slot (mesh_triangle.material) -> scene material index
    size_t slot_count;
    uint32_t default_material; ///< for triangles with no slot (material -1)
    char *path;                ///< file it was loaded from, to load each file once
} scene_mesh;

/// A file a scene was read from, by identity (device and inode): two spellings of a path are one file.
typedef struct scene_input {
    uint64_t dev, ino;
    char *path; ///< the path it was opened by (owned), to read it again for a checkpoint's identity
} scene_input;

/// The scene: plain data read from a scene file. The API hands it out as the opaque glint_scene, under this tag.
typedef struct glint_scene glint_scene;
struct glint_scene {
    char *path;            ///< scene file name, as given, for messages
    uint64_t text_hash;    ///< hash_bytes of the scene text (a file or standard input), for checkpoints
    render_settings settings;
    camera camera;

    material *materials;   ///< materials[i]; objects refer to them by index
    char **material_names; ///< NULL entry for anonymous (inline) materials
    size_t material_count;

    sphere *spheres;
    size_t sphere_count;

    light *lights;
    size_t light_count;

    quad *quads;             ///< world-space parallelograms (boxes are six of them)
    size_t quad_count;

    texture *textures;       ///< material.albedo_texture / emission_texture index these
    char **texture_names;    ///< NULL entry for anonymous (inline) textures
    size_t texture_count;

    scene_mesh *meshes;
    size_t mesh_count;
    sphere *instance_spheres; ///< object-space spheres of INSTANCE_SPHERE instances
    size_t instance_sphere_count;
    instance *instances;
    size_t instance_count;
    moving_sphere *moving_spheres; ///< spheres with a "center2"
    size_t moving_sphere_count;
    motion *motions;         ///< motions[k - 1]: how an instance with motion k moves
    size_t motion_count;
    uint32_t *importance_spheres; ///< world spheres diffuse bounces also aim at ("importance": book 3's glass)
    size_t importance_sphere_count;

    medium *media;           ///< participating media (objects of type constant_medium, homogeneous_medium)
    size_t medium_count;

    envmap environment;      ///< the background of BACKGROUND_ENVMAP (an empty image otherwise)

    scene_input *inputs;     ///< the files the scene was read from (scene file, meshes, MTL, images), each once
    size_t input_count;

    char **warnings;         ///< problems the loader worked around ("file:line: warning: ..."); never printed by the library
    size_t warning_count;

    /// The scene file reader's state kept for a scene built or extended call by call (scene/scene_calls.h): the
    /// names defined so far; NULL until the first call. Freed by session_free.
    struct scene_session *session;
    void (*session_free)(struct scene_session *session);

    /// Room allocated in each array above (core/array.h), in elements; the counts say how many are used.
    struct {
        size_t materials, material_names, spheres, lights, quads, textures, texture_names, meshes, instance_spheres,
            instances, warnings, inputs, moving_spheres, motions, media, importance_spheres;
    } capacity;
};

/// Appends a material and returns its index, or -1 when out of memory.
long scene_add_material(glint_scene *s, const material *m, const char *name);
/// Index of the named material, or -1.
long scene_find_material(const glint_scene *s, const char *name);
/// Appends a sphere; false when out of memory.
bool scene_add_sphere(glint_scene *s, sphere sp);
/// Appends a light; false when out of memory.
bool scene_add_light(glint_scene *s, light l);
/// Appends a quad; false when out of memory.
bool scene_add_quad(glint_scene *s, quad q);
/// Appends a medium; false when out of memory.
bool scene_add_medium(glint_scene *s, medium m);
/// Appends a texture, taking what it owns (freed on failure too); its index, or -1 when out of memory.
long scene_add_texture(glint_scene *s, texture *t, const char *name);
/// Index of the named texture, or -1.
long scene_find_texture(const glint_scene *s, const char *name);
/// Appends a mesh, taking its arrays and path (freed on failure too); its index, or -1 when out of memory.
long scene_add_mesh(glint_scene *s, scene_mesh *m);
/// Appends an object-space sphere for an INSTANCE_SPHERE instance; its index, or -1 when out of memory.
long scene_add_instance_sphere(glint_scene *s, sphere sp);
/// Appends an instance; false when out of memory.
bool scene_add_instance(glint_scene *s, instance in);
/// Appends a moving sphere; false when out of memory.
bool scene_add_moving_sphere(glint_scene *s, moving_sphere sp);
/// Marks world sphere `index` as one that diffuse bounces also sample directions towards; false when out of memory.
bool scene_add_importance_sphere(glint_scene *s, uint32_t index);
/// Appends a motion and returns the value of instance.motion that refers to it (its index + 1), or 0 when out
/// of memory.
uint32_t scene_add_motion(glint_scene *s, const motion *m);
/// Records that the scene was read from file (dev, ino), opened as `path`, once; false when out of memory.
bool scene_add_input(glint_scene *s, uint64_t dev, uint64_t ino, const char *path);
/// Whether path names one of the files the scene was read from (following symbolic links).
bool scene_reads_file(const glint_scene *s, const char *path);
/// Appends a copy of a warning message; false when out of memory.
bool scene_add_warning(glint_scene *s, const char *message);
/// An empty scene with every render setting at its documented default.
glint_scene *scene_new(const char *path);
/// Values that replace the scene file's render settings (glint_overrides, field for field); < 0 or NULL: keep.
typedef struct scene_overrides {
    long width, height, spp, max_depth;
    long long seed;
    const char *accel;           ///< "bvh", "bvh2" or "none"
    const char *output_encoding; ///< "linear", "gamma2" or "srgb"
    const char *sampler;         ///< "sobol" or "independent"
    double noise_threshold;      ///< adaptive sampling's threshold, 0 (off) to SCENE_MAX_NOISE_THRESHOLD; < 0: unset
} scene_overrides;
/// Applies command-line overrides, validated like scene values (GLINT_ERR_INPUT naming the flag otherwise).
glint_status scene_override(glint_scene *s, const scene_overrides *o, glint_error *err);
/// Reads a JSON scene from memory (docs/scene-format.md); `name` is used in messages and to resolve relative
/// paths. On failure *out is NULL and *err says "file:line:col: what is wrong, what was expected". Large mesh
/// files are read on `threads` threads (0: all online CPUs); the scene is the same for every count.
glint_status scene_file_parse(const char *name, const char *text, size_t length, int threads, glint_scene **out,
                              glint_error *err);
/// Reads a JSON scene file (at most 256 MiB).
glint_status scene_file_load(const char *path, int threads, glint_scene **out, glint_error *err);
/// The scene's geometry as the one value the accel is built over (geometry/geometry.h): its arrays, not copied,
/// and the camera's shutter. The value's list of meshes is `meshes` (mesh_count places, the caller's), which it
/// fills with the triangles of each scene mesh (their material slots stay the scene's business).
geometry_arrays scene_geometry(const glint_scene *s, const mesh **meshes);
/// Frees the scene and everything it owns (NULL is allowed).
void scene_free(glint_scene *s);
/// How many of each item a scene holds at one moment, so that a call that fails part-way can take back what it
/// added (scene_rollback): a scene built call by call stays as it was before the failed call.
typedef struct scene_mark {
    size_t materials, spheres, lights, quads, textures, meshes, instance_spheres, instances, moving_spheres, motions,
        importance_spheres, media, inputs, warnings;
} scene_mark;
/// The scene's counts now.
scene_mark scene_mark_now(const glint_scene *s);
/// Frees and drops every item added since `mark`.
void scene_rollback(glint_scene *s, const scene_mark *mark);

/// The background radiance seen along unit direction d.
static inline vec3 scene_background(const glint_scene *s, vec3 d) {
    const render_settings *rs = &s->settings;
    if (rs->background == BACKGROUND_SKY) return v3_lerp(rs->sky_horizon, rs->sky_zenith, 0.5f * (d.y + 1.0f));
    if (rs->background == BACKGROUND_ENVMAP) return envmap_radiance(&s->environment, d);
    return rs->background_color;
}

#endif
