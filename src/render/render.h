// render.h — the render loop: progressive sample passes over tiles on N threads, into a film.
#ifndef GLINT_RENDER_H
#define GLINT_RENDER_H

#include "core/status.h"
#include "integrator/integrator.h"
#include "scene/scene.h"

/// Hears the fraction of work done, from one thread at a time (glint_progress_fn's type).
typedef void (*render_progress_fn)(double fraction_done, void *user);
/// Hears the image being made (glint_live_image_fn's type; glint_render_options.live_image says when).
typedef void (*render_live_fn)(const glint_image *image, int spp_done, double fraction_done, void *user);

/// Counters of one render (glint_render_stats, field for field: the API copies them).
typedef struct render_stats {
    double wall_seconds, build_seconds;
    double render_seconds; ///< the render loop alone: wall_seconds less the preparation (BVH build)
    uint64_t samples, rays, shadow_rays, discarded_samples;
    uint64_t samples_resumed; ///< samples the resumed checkpoint held (not in `samples`, which this render took)
    uint64_t bvh_nodes, bvh_leaves, bvh_depth;
    int threads;
    int spp;      ///< samples per pixel the scene asked for
    int spp_done; ///< samples per pixel every pixel has (spp, or fewer under a time limit; 0 if stopped)
} render_stats;

/// Options of one render (the public glint_render_options and what only tests set).
typedef struct render_options {
    int threads;                   ///< worker threads (the render's and the BVH build's); 0 = all online CPUs
    double time_limit;             ///< > 0: no sample pass starts after this many seconds of rendering
    int region[4];                 ///< pixels X0 <= x < X1, Y0 <= y < Y1 to render; all zero: the whole image
    unsigned aovs;                 ///< AOV planes to render beside the colour (glint_aov bits); 0: none
    render_live_fn live_image;      ///< hears the image being made a few times a second and at the end (NULL: none)
    void *live_user;
    integrator_options integrator; ///< choices of the integrator that are not in the scene
    const char *checkpoint;        ///< a checkpoint file written after each pass and at the end, or NULL
    const char *resume;            ///< a checkpoint file the render continues, or NULL
    const atomic_int *cancel;      ///< nonzero: stop before the next sample (the caller's token); NULL: never
    accel_build_options accel;     ///< (tests) how the BVH is built: its knobs (stream_min_bytes, ...); its threads and
                                   ///< stop are the render's (threads, cancel), its no_presplit and no_spatial or-ed
                                   ///< with the scene's
} render_options;

/// Builds the render frame of s, renders every sample of the region's pixels into a new image (*out) of the
/// region's size, and frees the frame. On GLINT_ERR_INTERRUPTED *out holds the mean of each pixel's completed
/// samples; a region outside the image or empty is GLINT_ERR_INPUT, naming --region. With o->resume the render
/// starts from that checkpoint's samples (GLINT_ERR_INPUT, naming the file and what differs, for a checkpoint
/// of another render); with o->checkpoint it writes one after every pass and when it ends, stopped or not.
glint_status render_scene(const glint_scene *s, const render_options *o, render_progress_fn progress, void *user,
                          glint_image **out, render_stats *stats, glint_error *err);

#endif
