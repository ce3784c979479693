// tiles.h — the work items of a render: the region's cells of the full image's 16x16 tile grid and the sample
// passes (F, F, 2F, 4F, ... samples; F is 1 or TILES_FIRST_PASS), and one tile pass rendered into caller-given
// sums. The render loop (render.c) and glint-mpi (src/mpi/) cut the image the same way, so both give the same bytes.
#ifndef GLINT_TILES_H
#define GLINT_TILES_H

#include "core/status.h"
#include "core/stats.h"
#include "integrator/integrator.h"
#include "scene/scene.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

enum {
    TILES_SIZE = 16,       ///< a tile's side in pixels (edge tiles are clipped to the region)
    TILES_MAX_PASSES = 33, ///< 0, 1, 2, 4, ..., 2^30, spp: enough for any int spp
    /// The first pass of a render that no one watches fill and no time limit stops: a tile pass of 16x16 pixels at
    /// one sample is 256 paths, too few to fill the path tracer's stream (1,024 lanes), and each tile pass ends with
    /// its stream draining. The engine mesh at 16 spp, one thread: 9.22 Mrays/s in passes from 1, 9.98 from 16.
    /// At most FILM_ADAPTIVE_MIN_SAMPLES and a power of two: adaptive sampling's decisions fall where they did.
    TILES_FIRST_PASS = 16,
};

/// How a region's samples are cut into items: item = pass * tile_count + tile.
typedef struct tiles {
    int region[4];       ///< the pixels rendered, X0, Y0, X1, Y1 in full-image coordinates
    int tile_x0, tile_y0; ///< the full image's grid cell of the region's first tile
    int tiles_x, tile_count, pass_count;
    int pass_start[TILES_MAX_PASSES + 1]; ///< pass p renders samples [pass_start[p], pass_start[p + 1])
    int spp;
} tiles;

/// The region to render from a request (NULL or all zero: the whole image); GLINT_ERR_INPUT, naming --region,
/// unless it is a non-empty rectangle inside the image.
glint_status tiles_resolve_region(const render_settings *rs, const int *requested, int region[4], glint_error *err);
/// Cuts the (checked) region into tiles and spp samples into passes of first, first, 2 first, 4 first, ...
/// samples (the last one cut at spp): `first` is 1 where the image is watched as it fills or a time limit may
/// stop the render (a pass, once begun, runs to its end), TILES_FIRST_PASS otherwise. Any cut gives the same
/// bytes: a pixel's samples are summed in index order whatever the passes.
void tiles_init(tiles *t, const int region[4], int spp, int first);
/// The pixels [r[0], r[2]) x [r[1], r[3]) of tile `tile` (full-image coordinates).
void tiles_rect(const tiles *t, int tile, int r[4]);
/// Samples per pixel the tile's pass renders.
static inline int tiles_pass_samples(const tiles *t, int pass) { return t->pass_start[pass + 1] - t->pass_start[pass]; }

/// Renders pass `pass` of tile `tile` with the integrator, outside any film of the whole image: `sums` holds the
/// tile's running sums (its pixels in row order, 3 doubles each; read unless the pass is the first, updated
/// unless it is the last) and `means` receives each pixel's mean after the pass (3 floats each), exactly the
/// values the render loop's film holds for those pixels then. False when *stop cut the pass short (the outputs
/// are then incomplete and must be dropped).
bool tiles_render_pass(const tiles *t, const integrator *it, int tile, int pass, double *sums, float *means,
                       const atomic_int *stop, thread_stats *ts, _Atomic uint64_t *progress);

#endif
