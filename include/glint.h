// glint.h — the public API of the glint ray tracer: load a scene, render it, write the image.
//
// ABOUT
//   Two opaque handles, glint_scene (a scene: plain data, as a JSON scene file describes it) and glint_image
//   (a rendered image), created and freed only by the functions below. Four small structs are plain values
//   that the caller owns, fills or reads field by field: glint_error, glint_overrides, glint_render_options,
//   glint_render_stats. Nothing else is public: the command-line program uses this header alone, and
//   libglint.so exports the functions marked GLINT_API and nothing else.
//
// USAGE
//   glint_scene *scene; glint_image *image; glint_error err;
//   if (glint_scene_load("scene.json", &scene, &err) != GLINT_OK) { puts(err.message); return 2; }
//   glint_status st = glint_render(scene, NULL, NULL, NULL, &image, NULL, &err);
//   if (image) st = glint_image_write(image, "out.png", GLINT_FORMAT_AUTO, &err);
//   glint_image_free(image); glint_scene_free(scene);
//   Build: cc prog.c $(pkg-config --cflags --libs glint)     (add --static for libglint.a)
//
// Scenes come from JSON text (docs/scene-format.md) or are built call by call (glint_scene_new, then
// glint_scene_add_*: see "Scenes built in code" below), or both: a loaded scene can be extended by calls.
// A scene can be rendered any number of times, from one thread at a time; each render builds what it needs
// (BVH, light index, camera) from the scene as it is then, so overrides made between renders take effect.
#ifndef GLINT_H
#define GLINT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GLINT_VERSION "0.3.0"
#define GLINT_VERSION_MAJOR 0
#define GLINT_VERSION_MINOR 3
#define GLINT_VERSION_PATCH 0

/// Marks the public API: the library is built with hidden visibility, so libglint.so exports these alone.
#if defined(__GNUC__)
#define GLINT_API __attribute__((visibility("default")))
#else
#define GLINT_API
#endif

// glint_status (what a call did) and glint_error (why it failed): the vocabulary the library's every layer shares.
#define GLINT_PUBLIC_HEADER
#include "glint/status.h"
#undef GLINT_PUBLIC_HEADER

/// Opaque: a scene, plain data read from a scene file. Free with glint_scene_free.
typedef struct glint_scene glint_scene;
/// Opaque: a rendered image (linear RGB and its display encoding). Free with glint_image_free.
typedef struct glint_image glint_image;

/// A value struct: values that replace the scene file's render settings; a field < 0 (or NULL) leaves the
/// file's value. Initialise with glint_overrides_init, then set what changes.
typedef struct glint_overrides {
    long width, height, spp, max_depth;
    long long seed;
    const char *accel; ///< "bvh" (default), "bvh2" or "none"
    const char *output_encoding; ///< how 8-bit output encodes linear values: "linear", "gamma2" or "srgb"
    const char *sampler; ///< the path tracer's random numbers: "sobol" (default) or "independent"
    /// Adaptive sampling (the scene's "noise_threshold"): a pixel whose estimated relative error falls below this
    /// stops taking samples; 0: off (every pixel takes spp samples); < 0: the scene's value
    double noise_threshold;
} glint_overrides;

/// Sets every field of *o to "not overridden".
GLINT_API void glint_overrides_init(glint_overrides *o);

/// AOVs (arbitrary output variables): per-pixel data of the surfaces seen, rendered beside the colour when
/// glint_render_options.aovs asks (bits, or-ed), averaged over each pixel's samples exactly as the colour is,
/// the buffers a denoiser (Intel Open Image Denoise) or a compositor takes. See glint_image_aov.
typedef enum glint_aov {
    /// 3 floats a pixel in [0, 1]: the reflectance of the first diffuse or glossy surface seen (the path tracer
    /// looks past perfect mirrors and glass, tinted by them; the Whitted integrators record the first hit); an
    /// emitter's emission scaled to a largest channel of 1; the background's colour (clamped) where rays escape
    GLINT_AOV_ALBEDO = 1,
    /// 3 floats a pixel: the world-space unit shading normal of that surface, facing the ray; the mean over the
    /// pixel's samples is not renormalised; (0, 0, 0) where the camera sees only the background
    GLINT_AOV_NORMAL = 2,
    /// 1 float a pixel: the distance from the camera to the first surface hit along each sample's ray, the mean
    /// over the samples that hit one; +infinity where none did
    GLINT_AOV_DEPTH = 4,
    /// 1 float a pixel: the samples the pixel took (the scene's spp, or fewer where adaptive sampling stopped it:
    /// "noise_threshold")
    GLINT_AOV_SAMPLES = 8,
    GLINT_AOV_ALL = 15
} glint_aov;
/// Receives the image while it is being rendered (glint_render_options.live_image): the image (of the region's
/// size), the samples per pixel that every pixel has completed, and the fraction of all samples done.
typedef void (*glint_live_image_fn)(const glint_image *image, int spp_done, double fraction_done, void *user);

/// A value struct: options of one render that are not part of the scene (zero-initialised: the defaults). Every
/// field is a value field; initialise the whole struct ({0} or memset) so that fields added later stay default.
/// A cancel token: stops the renders given it (glint_render_options.cancel), and only those. Opaque.
typedef struct glint_cancel glint_cancel;

typedef struct glint_render_options {
    int threads; ///< worker threads (the render's and the BVH build's); 0 = all online CPUs. The image is the same for every count
    /// > 0: after this many seconds of rendering no new sample pass starts (passes are 1, 1, 2, 4, ...
    /// samples per pixel); the render ends with GLINT_OK once the pass in progress is complete, and its
    /// image is exactly that of a render at the samples per pixel reached (glint_render_stats.spp_done).
    double time_limit;
    /// Only the pixels X0 <= x < X1, Y0 <= y < Y1 of the full image, {X0, Y0, X1, Y1}; all zero = the whole
    /// image. Each pixel gets exactly the values it has in a full render; the image is the region's size and
    /// remembers where it lies (a PNG of it records that for glint_merge).
    int region[4];
    /// The AOVs to render beside the colour (glint_aov bits, or-ed); 0: none, and no cost. Other bits are
    /// GLINT_ERR_INPUT. glint_image_write writes them as channels of an OpenEXR file.
    unsigned aovs;
    /// When not NULL: called from one helper thread of the render (never two calls at once) every 0.2 s or so
    /// while it runs, and once more after the last sample (or the stop), with the image being made. During the
    /// render the workers are writing it: a pixel may be read mid-update (its channels from two passes); the last
    /// call sees the final values. The image may be read (glint_image_info, glint_image_rgb8) only during the
    /// call, never freed or kept. The time spent in the call is the caller's: keep it short (a preview window
    /// converts to 8 bits and returns). Rendering itself pays nothing for it.
    glint_live_image_fn live_image;
    void *live_user; ///< passed to live_image
    /// Not NULL: a checkpoint file, written (atomically, as images are) after every sample pass and when the
    /// render ends, completed, stopped or out of time: every pixel's count of samples and their sums, and what
    /// render they belong to (the bytes of the scene's files, the settings, the region). Rendering pauses while
    /// it is written; a write that fails ends the render with GLINT_ERR_RENDER.
    const char *checkpoint;
    /// Not NULL: a checkpoint file this render continues; the image is exactly that of an uninterrupted render
    /// (byte for byte, for any thread count). The scene's files and settings must be those it was made with,
    /// spp excepted (it may change, to no fewer than the samples a pixel of it has): GLINT_ERR_INPUT otherwise, the
    /// message naming the file and what differs, and for a file that is no checkpoint, truncated or corrupt.
    /// It may be the same file as checkpoint.
    const char *resume;
    /// Not NULL: a cancel token (glint_cancel_new). glint_cancel_request on it, from any thread or a signal
    /// handler, stops this render before its next sample: it returns GLINT_ERR_INTERRUPTED with the partial
    /// image (each pixel the mean of its completed samples; black when stopped during the BVH build). Each render
    /// may have a token of its own, so that renders in one process are stopped one by one; a token already
    /// requested stops the render at once. NULL: the render runs to its end.
    glint_cancel *cancel;
    /// Not NULL: values that replace the scene's settings for this render only (the scene is not changed), checked
    /// as glint_scene_override checks them. Several renders of one scene may each have their own.
    const glint_overrides *overrides;
    /// Not NULL: the caller's buffer of width * height * 3 floats (the rendered image's size: the region's when
    /// there is one), which receives the image's linear RGB values (row 0 at the top) when glint_render returns
    /// GLINT_OK or GLINT_ERR_INTERRUPTED; glint_render's `out` may then be NULL (no image is kept).
    float *rgb_out;
} glint_render_options;

/// A value struct: counters of one render, filled by glint_render.
typedef struct glint_render_stats {
    double wall_seconds, build_seconds;
    double render_seconds; ///< the render loop alone: wall_seconds less the preparation (BVH build)
    uint64_t samples, rays, shadow_rays, discarded_samples;
    uint64_t samples_resumed; ///< samples the resumed checkpoint held (not in `samples`, which this render took)
    uint64_t bvh_nodes, bvh_leaves, bvh_depth;
    int threads;
    int spp;      ///< samples per pixel the scene asked for
    int spp_done; ///< samples per pixel every pixel has (spp, or fewer under a time limit; 0 if stopped)
} glint_render_stats;

/// Called from one thread at a time with the fraction of work done, a few times a second at most.
typedef void (*glint_progress_fn)(double fraction_done, void *user);

/// Largest scene text accepted, in bytes (256 MiB); a reader of other sources (standard input) stops there.
#define GLINT_MAX_SCENE_BYTES ((size_t)256 << 20)
/// Reads and validates a JSON scene file; on failure returns GLINT_ERR_INPUT (GLINT_ERR_RENDER when memory
/// runs out) with a message in *err, and *out is NULL.
GLINT_API glint_status glint_scene_load(const char *path, glint_scene **out, glint_error *err);
/// Parses a JSON scene from memory; `name` is used in messages and to resolve relative paths.
GLINT_API glint_status glint_scene_parse(const char *name, const char *text, size_t length, glint_scene **out,
                                         glint_error *err);
/// A value struct: options of reading a scene (zero-initialised: the defaults, those of glint_scene_load).
typedef struct glint_load_options {
    int threads; ///< threads that read a large mesh file; 0 = all online CPUs. The scene is the same for every count
} glint_load_options;
/// glint_scene_load with options (opt may be NULL: the defaults).
GLINT_API glint_status glint_scene_load_with(const char *path, const glint_load_options *opt, glint_scene **out,
                                             glint_error *err);
/// glint_scene_parse with options (opt may be NULL: the defaults).
GLINT_API glint_status glint_scene_parse_with(const char *name, const char *text, size_t length,
                                              const glint_load_options *opt, glint_scene **out, glint_error *err);
/// Applies command-line overrides, validated like scene values (GLINT_ERR_INPUT naming the flag otherwise); adds
/// a warning when the scene will render by brute force (accel "none") with meshes in it.
GLINT_API glint_status glint_scene_override(glint_scene *scene, const glint_overrides *o, glint_error *err);
/// Image size the scene will render at.
GLINT_API void glint_scene_size(const glint_scene *scene, int *width, int *height);
/// Number of warnings collected (problems in mesh files the loader worked around, brute force on meshes); the
/// library prints none.
GLINT_API size_t glint_scene_warning_count(const glint_scene *scene);
/// Warning i (0-based), formatted "file:line: warning: what happened; what is done instead" (a warning about the
/// settings: "warning: setting: what will happen"), or NULL past the end.
GLINT_API const char *glint_scene_warning(const glint_scene *scene, size_t i);
/// Whether `path` names a file the scene was read from (the scene file, its meshes, image textures, environment
/// map; symbolic links followed): a program that writes an image should refuse to overwrite one.
GLINT_API bool glint_scene_reads_file(const glint_scene *scene, const char *path);
/// Frees a scene (NULL is allowed).
GLINT_API void glint_scene_free(glint_scene *scene);

// ---------------------------------------------------------------------------------------------------------------
// Scenes built in code
//
// A scene file's every part can be given by calls instead: the render settings, the camera, named textures and
// materials, objects and lights, each as a glint_params: named values, exactly the keys and values of the JSON
// object the scene format documents for it (docs/scene-format.md). Each call hands its value to the scene file's
// own reader, so a scene built in code is checked by the same code and fails with the same message as a file,
// opened by the call's name instead of "file:line:col": "glint_scene_add_object: object 0 (sphere): "radius" must
// be a finite non-zero number, got 0". A call that fails leaves the scene as it was. Triangle meshes and images,
// which a file names by path, come from the caller's arrays (glint_scene_add_mesh, glint_scene_add_image), copied.
//
//   glint_scene *s; glint_error err;
//   glint_scene_new("my scene", &s, &err);
//   glint_params *p = glint_params_new();
//   glint_params_string(p, "type", "lambertian"); glint_params_numbers(p, "albedo", (double[]){0.8, 0.3, 0.3}, 3);
//   glint_scene_add_material(s, "red", p, &err);   glint_params_free(p);
//   p = glint_params_new();
//   glint_params_string(p, "type", "sphere"); glint_params_numbers(p, "center", (double[]){0, 0, -1}, 3);
//   glint_params_number(p, "radius", 0.5); glint_params_string(p, "material", "red");
//   if (glint_scene_add_object(s, p, &err) != GLINT_OK) puts(err.message);
//   glint_params_free(p);
//
// A scene is changed from one thread at a time, and not while it renders.

/// Opaque: named values, one JSON object of the scene format (a material, an object, the camera...).
typedef struct glint_params glint_params;
/// New, empty parameters; NULL when out of memory. Free with glint_params_free.
GLINT_API glint_params *glint_params_new(void);
/// Frees parameters (NULL is allowed).
GLINT_API void glint_params_free(glint_params *p);
// The setters replace a value the key had. A setter that runs out of memory marks p, and the call given p then
// fails with GLINT_ERR_RENDER: the setters themselves need no checks.
/// key: a number (JSON number; the scene format checks its range and, where it wants one, that it is an integer).
GLINT_API void glint_params_number(glint_params *p, const char *key, double value);
/// key: an array of n numbers (a vector or colour: n = 3; a matrix: 16; shutter [open, close]: 2).
GLINT_API void glint_params_numbers(glint_params *p, const char *key, const double *values, size_t n);
/// key: a string (a type, a material or texture name, a file path); NULL sets JSON null.
GLINT_API void glint_params_string(glint_params *p, const char *key, const char *value);
/// key: true or false.
GLINT_API void glint_params_bool(glint_params *p, const char *key, bool value);
/// key: an object (a copy of `value`): an inline material, texture or background.
GLINT_API void glint_params_object(glint_params *p, const char *key, const glint_params *value);
/// Appends a copy of `item` to the array `key` (made on first use): the operations of a "transform".
GLINT_API void glint_params_append(glint_params *p, const char *key, const glint_params *item);
/// key: any JSON value, from JSON text (a Perlin table, a whole transform); GLINT_ERR_INPUT ("glint_params_json:
/// line:col: what is wrong") for text that is not JSON.
GLINT_API glint_status glint_params_json(glint_params *p, const char *key, const char *json, glint_error *err);
/// New parameters from the JSON text of an object; GLINT_ERR_INPUT for text that is not one.
GLINT_API glint_status glint_params_parse(const char *json, glint_params **out, glint_error *err);

/// A new scene with every setting at its documented default and nothing in it. `name` (NULL: "<scene>") stands
/// for the scene file's name: relative file paths in values (textures, meshes, environment maps) resolve against
/// its directory ("models/" or "models/x.json": models/; "x": the current directory).
GLINT_API glint_status glint_scene_new(const char *name, glint_scene **out, glint_error *err);
/// The "render" object: the keys given replace the scene's values (an absent "max_depth" follows the integrator, as
/// in a file). Without "output", 8-bit output follows the integrator (paper mode linear, else sRGB).
GLINT_API glint_status glint_scene_set_render(glint_scene *scene, const glint_params *render, glint_error *err);
/// The "camera" object (a "lookat" or "viewport" camera): replaces the camera.
GLINT_API glint_status glint_scene_set_camera(glint_scene *scene, const glint_params *camera, glint_error *err);
/// A named texture, as in "textures" (name: 1 to 128 bytes, unused).
GLINT_API glint_status glint_scene_add_texture(glint_scene *scene, const char *name, const glint_params *texture,
                                               glint_error *err);
/// A named material, as in "materials"; objects refer to it by name.
GLINT_API glint_status glint_scene_add_material(glint_scene *scene, const char *name, const glint_params *material,
                                                glint_error *err);
/// An object, as an element of "objects" (sphere, quad, box, mesh, media). A "mesh" object places a mesh file
/// ("file") or a mesh added with glint_scene_add_mesh ("mesh": its name), once per call: the instances of one mesh
/// share its triangles.
GLINT_API glint_status glint_scene_add_object(glint_scene *scene, const glint_params *object, glint_error *err);
/// A light, as an element of "lights".
GLINT_API glint_status glint_scene_add_light(glint_scene *scene, const glint_params *light, glint_error *err);
/// A triangle mesh in the caller's arrays, copied by glint_scene_add_mesh (they may be freed after the call).
typedef struct glint_mesh_data {
    size_t vertex_count;
    const float *positions;   ///< 3 floats a vertex, finite
    const float *normals;     ///< 3 floats a vertex (need not be unit), or NULL: smooth normals are computed (as for
                              ///< an OBJ file without normals: each vertex the area-weighted mean of its triangles')
    const float *uvs;         ///< 2 floats a vertex (texture coordinates, v = 1 at an image's top row), or NULL
    size_t triangle_count;    ///< at least 1
    const uint32_t *indices;  ///< 3 vertex indices a triangle, each < vertex_count; counter-clockwise is the front
    const uint32_t *face_materials; ///< a triangle's index into `materials`, or NULL: the placing object's material
    const char *const *materials;   ///< names of materials added before (glint_scene_add_material)
    size_t material_count;
    bool flat; ///< shade each triangle with its geometric normal (as "face_normals": true); normals must be NULL
} glint_mesh_data;
/// Adds a mesh under `name` (1 to 128 bytes, unused) for "mesh" objects to place: {"type": "mesh", "mesh": name,
/// "transform": [...], "material": ...}; faces without a material of their own are grey unless the object gives
/// one. GLINT_ERR_INPUT names the first bad value: "glint_scene_add_mesh: indices[7] (triangle 2) is 9, but the
/// mesh has 8 vertices".
///   float xyz[] = {0,0,0, 1,0,0, 0,1,0};  uint32_t tri[] = {0, 1, 2};
///   glint_mesh_data m = {.vertex_count = 3, .positions = xyz, .triangle_count = 1, .indices = tri};
///   glint_scene_add_mesh(s, "tri", &m, &err);
///   glint_params_parse("{\"type\": \"mesh\", \"mesh\": \"tri\", \"material\": \"red\"}", &p, &err);
///   glint_scene_add_object(s, p, &err);     (as many objects as instances are wanted, each with its transform)
GLINT_API glint_status glint_scene_add_mesh(glint_scene *scene, const char *name, const glint_mesh_data *mesh,
                                            glint_error *err);
/// Pixels in the caller's array, row 0 at the top, copied.
typedef struct glint_pixels {
    int width, height; ///< at most 2^24 pixels in all, as for image files
    int channels;      ///< 1 (grey), 3 (RGB) or 4 (RGBA; alpha is linear in [0, 1], for pbr's alpha masks)
    const float *values;  ///< linear values >= 0, or NULL
    const uint8_t *bytes; ///< 8-bit values, decoded as the options' "encoding" says (default "srgb"), or NULL
} glint_pixels;
/// Adds a named image texture from pixels (exactly one of values and bytes); `options` (may be NULL) holds the
/// image texture's "encoding" and "filter" (docs/scene-format.md, textures). Materials then name it:
///   uint8_t rgb[] = {255,0,0, 0,0,255};  glint_pixels px = {2, 1, 3, NULL, rgb};
///   glint_scene_add_image(s, "stripes", &px, NULL, &err);    // {"type": "lambertian", "albedo": "stripes"}
GLINT_API glint_status glint_scene_add_image(glint_scene *scene, const char *name, const glint_pixels *pixels,
                                             const glint_params *options, glint_error *err);

/// Renders the scene: builds what the render needs from it (BVH, light index, camera), renders every sample
/// of opt->region (the whole image by default) on opt->threads threads (opt may be NULL), frees what it built;
/// a region that is empty or not inside the image is GLINT_ERR_INPUT, its message naming --region. progress
/// (may be NULL) hears how far it is; stats (may be NULL) receives the counters. On GLINT_OK and
/// GLINT_ERR_INTERRUPTED *out is the image (of the region's size; after an interruption, each pixel the mean
/// of its completed samples); otherwise *out is NULL.
GLINT_API glint_status glint_render(const glint_scene *scene, const glint_render_options *opt,
                                    glint_progress_fn progress, void *user, glint_image **out,
                                    glint_render_stats *stats, glint_error *err);

/// A new cancel token, not requested (glint_render_options.cancel); NULL when out of memory.
GLINT_API glint_cancel *glint_cancel_new(void);
/// Asks the renders that use the token to stop before their next sample; async-signal-safe (it stores one
/// atomic flag), callable from any thread.
GLINT_API void glint_cancel_request(glint_cancel *cancel);
/// Whether glint_cancel_request was called on the token (since glint_cancel_reset).
GLINT_API bool glint_cancel_requested(const glint_cancel *cancel);
/// Makes the token unrequested again, for another render.
GLINT_API void glint_cancel_reset(glint_cancel *cancel);
/// Frees a token no render uses any more (NULL is allowed).
GLINT_API void glint_cancel_free(glint_cancel *cancel);

/// Image output format, chosen from the file name's extension unless given.
typedef enum glint_format {
    GLINT_FORMAT_AUTO,
    GLINT_FORMAT_PNG,
    GLINT_FORMAT_PPM,
    GLINT_FORMAT_PPM_ASCII,
    GLINT_FORMAT_PFM,
    GLINT_FORMAT_EXR,      ///< OpenEXR, linear RGB as 32-bit floats (.exr)
    GLINT_FORMAT_EXR_HALF, ///< OpenEXR, linear RGB as 16-bit halves
    GLINT_FORMAT_HDR       ///< Radiance RGBE, linear (.hdr)
} glint_format;

/// Writes the image; "-" writes PPM to standard output. An OpenEXR file holds the image's AOVs too, as channels
/// albedo.R, albedo.G, albedo.B, normal.X, normal.Y, normal.Z and Z (32-bit float even with
/// GLINT_FORMAT_EXR_HALF); the other formats hold the colour alone. An OpenEXR file of a region has the region
/// as its data window inside the full image's display window. The PNG of a region (glint_render_options.region)
/// holds a tEXt chunk "glint:region" = "X0,Y0,X1,Y1,W,H" (W x H: the full image) for glint_merge. PFM has no room
/// for it: the PFM of a region at PATH (and each AOV PFM of glint_image_write_aov) is followed by a region file
/// PATH.region, two lines "glint:region=X0,Y0,X1,Y1,W,H" and "fnv1a64=" with the 64-bit FNV-1a hash of the PFM's
/// bytes as 16 lowercase hex digits, written as images are (none for standard output). PPM and HDR hold the
/// region's pixels alone. A whole image's PNG has no such chunk, nor its PFM a region file. Writes an
/// unnamed temporary file (Linux O_TMPFILE; a named one where unsupported) and links it into place, so a
/// failed or killed write leaves no file behind; writes through a symbolic link to the file it names, and
/// refuses a read-only file ("PATH: cannot write: the file is read-only", GLINT_ERR_RENDER).
GLINT_API glint_status glint_image_write(const glint_image *img, const char *path, glint_format format,
                                         glint_error *err);
/// Writes one AOV plane of the image (a single glint_aov bit) to a .pfm file, as glint_image_write writes
/// files: "PF" (RGB) for albedo and normal, "Pf" (grey) for depth, little-endian floats, rows from the bottom
/// up: the inputs Intel Open Image Denoise's oidnDenoise reads. GLINT_ERR_INPUT for another extension or an AOV
/// the image does not hold. (An OpenEXR file written by glint_image_write holds every AOV as channels.)
GLINT_API glint_status glint_image_write_aov(const glint_image *img, glint_aov aov, const char *path,
                                             glint_error *err);
/// Checks before a render that the image can be written there: GLINT_ERR_INPUT for an unknown extension,
/// GLINT_ERR_RENDER ("PATH: cannot write: reason") for a missing or unwritable directory or a read-only file.
GLINT_API glint_status glint_image_check_path(const char *path, glint_format format, glint_error *err);
/// Width, height and linear RGB pixels (row 0 at the top, 3 floats a pixel), valid until glint_image_free.
GLINT_API void glint_image_info(const glint_image *img, int *width, int *height, const float **rgb);
/// The 8-bit, display-encoded pixel (x, y) channel c, exactly as PNG/PPM output stores it.
GLINT_API uint8_t glint_image_byte(const glint_image *img, int x, int y, int c);
/// The plane of one AOV (a single glint_aov bit) that the image holds: width * height pixels, row 0 at the top,
/// *channels floats a pixel (3 for albedo and normal, 1 for depth), valid until glint_image_free; NULL (and
/// *channels 0) when the render did not ask for it. channels may be NULL.
GLINT_API const float *glint_image_aov(const glint_image *img, glint_aov aov, int *channels);
/// Fills rgb (width * height * 3 bytes, row 0 at the top) with the image's 8-bit, display-encoded values: exactly
/// glint_image_byte of every pixel and channel, in one pass fast enough for a live preview.
GLINT_API void glint_image_rgb8(const glint_image *img, uint8_t *rgb);
/// Frees an image (NULL is allowed).
GLINT_API void glint_image_free(glint_image *img);
/// An image of the caller's linear RGB values (width * height * 3 floats, row 0 at the top, copied), to write with
/// glint_image_write in any format; output_encoding ("linear", "gamma2", "srgb"; NULL: "srgb") says how 8-bit
/// formats encode them:  glint_image_from_rgb(w, h, rgb, NULL, &img, &err); glint_image_write(img, "x.png", 0, &err);
GLINT_API glint_status glint_image_from_rgb(int width, int height, const float *rgb, const char *output_encoding,
                                            glint_image **out, glint_error *err);

/// Assembles the files of regions (written by glint_image_write with glint_render_options.region) into the full
/// image and writes it to `output`; the parts must tile it exactly, in any order:
/// - 8-bit parts: PNG files (placed by their "glint:region" chunk) to .png or .ppm, the parts' bytes unchanged;
/// - float parts: OpenEXR files (placed by their data windows; every channel glint writes: R, G, B and the AOV
///   channels, the same in every part) and PFM files (placed by their region file PATH.region, which must be
///   the one written with that PFM: its hash is checked) to .exr, .pfm or .hdr, with the parts' float values
///   exactly: the merge equals the full render's file. An .exr holds every channel, as 16-bit halves when every
///   part's colour (and albedo and normal) channels are halves, else as 32-bit floats (which hold halves
///   exactly); a .pfm or .hdr holds the colour alone (HDR rounds it to RGBE). Grey PFM parts ("Pf", a depth AOV)
///   merge to .pfm alone.
/// GLINT_ERR_INPUT, naming the part, for a file that is no region part, 8-bit parts with float parts, a float
/// output from 8-bit parts or an 8-bit output from float parts, parts of different full sizes or channels,
/// overlapping parts, a pixel no part covers, an output that is one of the parts, and a damaged or truncated
/// part; GLINT_ERR_RENDER for I/O and memory (a float merge holds the full image as 32-bit floats: 4 bytes a
/// channel a pixel, plus 1).
GLINT_API glint_status glint_merge(const char *output, const char *const *parts, size_t count, glint_error *err);

/// Opaque: a timeline of the library's work, for seeing where the threads' time goes (load balance, stalls). It
/// records what happens on the threads attached to it (glint_trace_attach) and on the worker threads of the
/// renders they run: scene loading (JSON parse, OBJ meshes, textures, environment map), the BVH build, each tile
/// pass on each worker (with its x, y, w, h, pass), each sample pass, waits between passes, checkpoint and
/// image writes. glint_trace_write saves it as Chrome trace-event JSON, the format Perfetto
/// (https://ui.perfetto.dev) and chrome://tracing open. A thread with no trace attached records nothing and pays
/// one test of a pointer per tile; the images are the same bytes with or without a trace. Free with
/// glint_trace_free.
typedef struct glint_trace glint_trace;

/// A new, empty trace whose time 0 is now; NULL when out of memory.
GLINT_API glint_trace *glint_trace_new(void);
/// From now on the library's work on the calling thread is recorded in trace, on a timeline row (a "thread")
/// named thread_name, such as "main"; a render started on this thread adds the rows "worker 1", "worker 2", ...
/// for its other threads (its calling thread is its worker 0) and "sample passes". Attaching a thread again to
/// the same trace keeps its row; trace NULL detaches it. GLINT_ERR_RENDER when memory runs out.
GLINT_API glint_status glint_trace_attach(glint_trace *trace, const char *thread_name, glint_error *err);
/// The CPUs this process may run on (its affinity mask: taskset, cgroups, an MPI launcher's binding; else the
/// online CPUs), at least 1: the number of threads a thread count of 0 means.
GLINT_API int glint_cpu_count(void);
/// Whether writing at path a and at path b would write one file: the same existing file (by device and inode,
/// whatever the names and symbolic links), or, for names that do not exist yet, the same name in the same
/// directory ("x.pfm" and "./x.pfm"). Tools that write several files check with it that none replaces another.
GLINT_API bool glint_path_same_target(const char *a, const char *b);
/// Checks before a render that a trace can be written at path: GLINT_ERR_RENDER ("PATH: cannot write: reason")
/// for a missing or unwritable directory or a read-only file.
GLINT_API glint_status glint_trace_check_path(const char *path, glint_error *err);
/// Writes the trace to path as JSON ({"traceEvents":[...],"displayTimeUnit":"ms"}: complete events, "ph":"X",
/// with ts and dur in microseconds since glint_trace_new, and thread_name metadata), as glint_image_write writes
/// images: a temporary file linked into place, nothing left behind on failure. Call it when the renders it
/// records have returned. GLINT_ERR_RENDER when the file cannot be written, or when memory ran out while events
/// were recorded (a timeline with holes is not written); GLINT_ERR_INPUT when trace or path is NULL.
GLINT_API glint_status glint_trace_write(glint_trace *trace, const char *path, glint_error *err);
/// Frees a trace (NULL is allowed) and detaches the calling thread from it; detach any other thread first.
GLINT_API void glint_trace_free(glint_trace *trace);

/// The library's version, GLINT_VERSION when the header and the library agree.
GLINT_API const char *glint_version(void);

#ifdef __cplusplus
}
#endif
#endif
