// checkpoint.h — a render's state on disk (--checkpoint, --resume): which render it is (the scene's files and
// the settings), and planes of per-pixel data (samples completed, their sums), so that a stopped render can be
// continued to exactly the image an uninterrupted one makes. The file format is in docs/architecture.md.
#ifndef GLINT_CHECKPOINT_H
#define GLINT_CHECKPOINT_H

#include "core/status.h"
#include "scene/scene.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// Version of the file format this glint writes and reads.
#define CHECKPOINT_VERSION 2u

/// What a checkpoint is a checkpoint of: a resumed render must match it in every field.
typedef struct checkpoint_identity {
    const char *scene_name; ///< the scene file as named when the checkpoint was made (messages only)
    uint64_t scene_hash;    ///< the scene text and the bytes of every file it read (checkpoint_scene_hash)
    uint64_t seed;
    int32_t width, height, max_depth;
    int32_t integrator, whitted_mode, accel, encoding; ///< integrator_kind, whitted_mode, accel_kind, output_transform
    int32_t light_sampling; ///< 1 unless the path tracer's next-event estimation is off (integrator_options)
    int32_t region[4];      ///< X0, Y0, X1, Y1: the pixels the planes hold, row by row
    int32_t sampler;        ///< sampler_kind
    float noise_threshold;  ///< adaptive sampling's threshold (render_settings.noise_threshold; 0: off)
} checkpoint_identity;

/// Element types of planes.
typedef enum checkpoint_type { CHECKPOINT_U32 = 1, CHECKPOINT_F64 = 2 } checkpoint_type;

/// One plane: `components` values of `type` per pixel of the region, pixels row by row (interleaved).
typedef struct checkpoint_plane {
    const char *name; ///< at most 15 bytes: "count" (samples completed), "rgb" (their sums)
    checkpoint_type type;
    uint32_t components;
    void *data;       ///< written from, or read into (the caller's buffer of the plane's size)
} checkpoint_plane;

/// The hash of s's text and of the bytes of every file it read (meshes, material libraries, textures,
/// environment map; read again now): GLINT_ERR_INPUT naming a file that can no longer be read.
glint_status checkpoint_scene_hash(const glint_scene *s, uint64_t *hash, glint_error *err);

/// The identity of a render of s over region (light_sampling: see checkpoint_identity); hashes the scene's
/// files (checkpoint_scene_hash).
glint_status checkpoint_identity_of(const glint_scene *s, const int region[4], bool light_sampling,
                                    checkpoint_identity *id, glint_error *err);

/// Writes a checkpoint of the render `id` at `spp` samples per pixel, every pixel having at least `complete`,
/// with its planes, through image_write_file (atomic: a kill leaves the old file or the new one).
glint_status checkpoint_write(const char *path, const checkpoint_identity *id, int spp, int complete,
                              const checkpoint_plane *planes, size_t plane_count, glint_error *err);

/// Opens the checkpoint at path as checkpoint_read does, without reading it: GLINT_ERR_INPUT ("PATH: cannot open
/// the checkpoint: reason") for a missing, unreadable or non-regular file (directory, FIFO, device).
glint_status checkpoint_check_readable(const char *path, glint_error *err);

/// Reads the checkpoint at path into the planes the caller names (each must be in the file with that type and
/// components; the file's other planes are skipped). GLINT_ERR_INPUT ("PATH: what is wrong") for a file that is
/// no checkpoint, of another version or byte order, truncated or corrupt (checksums), or of a render other than
/// `id` (the message names what differs); GLINT_ERR_RENDER when memory runs out. *spp: the spp it was made for.
glint_status checkpoint_read(const char *path, const checkpoint_identity *id, checkpoint_plane *planes,
                             size_t plane_count, int *spp, glint_error *err);

#endif
