// render.h — the render loop: progressive sample passes over tiles on N threads, into a film.
#ifndef GLINT_RENDER_H
#define GLINT_RENDER_H

#include "glint.h"
#include "integrator/integrator.h"
#include "scene/scene.h"

/// Options of one render (the public glint_render_options and what only tests set).
typedef struct render_options {
    int threads;                   ///< worker threads (the render's and the BVH build's); 0 = all online CPUs
    double time_limit;             ///< > 0: no sample pass starts after this many seconds of rendering
    int region[4];                 ///< pixels X0 <= x < X1, Y0 <= y < Y1 to render; all zero: the whole image
    unsigned aovs;                 ///< AOV planes to render beside the colour (glint_aov bits); 0: none
    glint_live_image_fn live_image; ///< hears the image being made a few times a second and at the end (NULL: none)
    void *live_user;
    integrator_options integrator; ///< choices of the integrator that are not in the scene
    const char *checkpoint;        ///< a checkpoint file written after each pass and at the end, or NULL
    const char *resume;            ///< a checkpoint file the render continues, or NULL
    const atomic_int *cancel;      ///< nonzero: stop before the next sample (the caller's token); NULL: never
} render_options;

/// Builds the render frame of s, renders every sample of the region's pixels into a new image (*out) of the
/// region's size, and frees the frame. On GLINT_ERR_INTERRUPTED *out holds the mean of each pixel's completed
/// samples; a region outside the image or empty is GLINT_ERR_INPUT, naming --region. With o->resume the render
/// starts from that checkpoint's samples (GLINT_ERR_INPUT, naming the file and what differs, for a checkpoint
/// of another render); with o->checkpoint it writes one after every pass and when it ends, stopped or not.
glint_status render_scene(const glint_scene *s, const render_options *o, glint_progress_fn progress, void *user,
                          glint_image **out, glint_render_stats *stats, glint_error *err);

#endif
