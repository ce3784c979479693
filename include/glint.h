// glint.h — the public API of the glint ray tracer: load a scene, render it, write the image.
// Every type is an opaque handle; the command-line program uses nothing else.
#ifndef GLINT_H
#define GLINT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GLINT_VERSION "0.1.0"

/// Marks the public API: the library is built with hidden visibility, so libglint.so exports these alone.
#if defined(__GNUC__)
#define GLINT_API __attribute__((visibility("default")))
#else
#define GLINT_API
#endif

/// Exit codes shared by the library's status values and the command-line program.
typedef enum glint_status {
    GLINT_OK = 0,
    GLINT_ERR_RENDER = 1, ///< rendering, memory or I/O failure
    GLINT_ERR_INPUT = 2,  ///< bad usage, scene file or mesh
    GLINT_ERR_INTERRUPTED = 3 ///< the render was stopped by glint_request_stop (partial image kept)
} glint_status;

/// A human-readable error, already formatted as "file:line:col: what is wrong, what was expected".
typedef struct glint_error {
    char message[1024];
} glint_error;

typedef struct glint_scene glint_scene;
typedef struct glint_image glint_image;

/// Values that replace the scene file's render settings; a field < 0 (or NULL) leaves the file's value.
typedef struct glint_overrides {
    long width, height, spp, max_depth;
    long long seed;
    const char *accel; ///< "bvh" (default), "bvh2" or "none"
} glint_overrides;

/// Sets every field of *o to "not overridden".
GLINT_API void glint_overrides_init(glint_overrides *o);

/// Options of one render that are not part of the scene.
typedef struct glint_render_options {
    int threads; ///< worker threads; 0 = all online CPUs
} glint_render_options;

/// Counters of one render, filled by glint_render.
typedef struct glint_render_stats {
    double wall_seconds, build_seconds;
    double render_seconds; ///< the render loop alone: wall_seconds less scene preparation (BVH build)
    uint64_t samples, rays, shadow_rays, discarded_samples;
    uint64_t bvh_nodes, bvh_leaves, bvh_depth;
    int threads;
} glint_render_stats;

/// Called from one worker thread at a time with the fraction of work done, a few times a second at most.
typedef void (*glint_progress_fn)(double fraction_done, void *user);

/// Reads and validates a JSON scene file; on failure returns GLINT_ERR_INPUT with a message in *err.
GLINT_API glint_status glint_scene_load(const char *path, glint_scene **out, glint_error *err);
/// Parses a JSON scene from memory; `name` is used in messages and to resolve relative paths.
GLINT_API glint_status glint_scene_parse(const char *name, const char *text, size_t length, glint_scene **out, glint_error *err);
/// Applies command-line overrides; validates them like scene values.
GLINT_API glint_status glint_scene_override(glint_scene *scene, const glint_overrides *o, glint_error *err);
/// Image size the scene will render at.
GLINT_API void glint_scene_size(const glint_scene *scene, int *width, int *height);
/// Number of warnings the loader collected (problems in mesh files it worked around); the library prints none.
GLINT_API size_t glint_scene_warning_count(const glint_scene *scene);
/// Warning i (0-based), formatted "file:line: warning: what happened; what is done instead", or NULL past the end.
GLINT_API const char *glint_scene_warning(const glint_scene *scene, size_t i);
GLINT_API void glint_scene_free(glint_scene *scene);

/// Renders the scene: builds what the render needs (BVH, light index, camera) from it, renders, frees that. On GLINT_ERR_INTERRUPTED *out still holds the samples completed so far.
GLINT_API glint_status glint_render(const glint_scene *scene, const glint_render_options *opt, glint_progress_fn progress,
                                    void *user, glint_image **out, glint_render_stats *stats, glint_error *err);

/// Asks running renders to stop soon; async-signal-safe (it stores one atomic flag).
GLINT_API void glint_request_stop(void);

/// Image output format, chosen from the file name's extension unless given.
typedef enum glint_format { GLINT_FORMAT_AUTO, GLINT_FORMAT_PNG, GLINT_FORMAT_PPM, GLINT_FORMAT_PPM_ASCII, GLINT_FORMAT_PFM } glint_format;

/// Writes the image; "-" writes PPM to standard output. Writes a temporary file and renames it.
GLINT_API glint_status glint_image_write(const glint_image *img, const char *path, glint_format format, glint_error *err);
/// Checks before a render that the image can be written there: GLINT_ERR_INPUT for an unknown extension,
/// GLINT_ERR_RENDER ("PATH: cannot write: reason") for a missing or unwritable directory.
GLINT_API glint_status glint_image_check_path(const char *path, glint_format format, glint_error *err);
/// Width, height and linear RGB pixels (row 0 at the top, 3 floats a pixel).
GLINT_API void glint_image_info(const glint_image *img, int *width, int *height, const float **rgb);
/// The 8-bit, display-encoded pixel (x, y) channel c, exactly as PNG/PPM output stores it.
GLINT_API uint8_t glint_image_byte(const glint_image *img, int x, int y, int c);
GLINT_API void glint_image_free(glint_image *img);

GLINT_API const char *glint_version(void);

#ifdef __cplusplus
}
#endif
#endif
