// tiles.c — the region's tiles and sample passes, and one tile pass rendered outside a whole-image film.
#include "render/tiles.h"
#include "film/film.h"

#include <stdio.h>
#include <string.h>

glint_status tiles_resolve_region(const render_settings *rs, const int *r, int region[4], glint_error *err) {
    if (!r || (r[0] == 0 && r[1] == 0 && r[2] == 0 && r[3] == 0)) {
        region[0] = region[1] = 0;
        region[2] = rs->width;
        region[3] = rs->height;
        return GLINT_OK;
    }
    if (r[0] >= r[2] || r[1] >= r[3]) {
        snprintf(err->message, sizeof err->message, "--region: %d,%d,%d,%d is empty, expected X0 < X1 and Y0 < Y1",
                 r[0], r[1], r[2], r[3]);
        return GLINT_ERR_INPUT;
    }
    if (r[0] < 0 || r[1] < 0 || r[2] > rs->width || r[3] > rs->height) {
        snprintf(err->message, sizeof err->message,
                 "--region: %d,%d,%d,%d is not inside the %dx%d image, expected 0 <= X0 < X1 <= %d and "
                 "0 <= Y0 < Y1 <= %d", r[0], r[1], r[2], r[3], rs->width, rs->height, rs->width, rs->height);
        return GLINT_ERR_INPUT;
    }
    memcpy(region, r, 4 * sizeof *region);
    return GLINT_OK;
}

// Pass boundaries 0, first, 2 first, 4 first, ..., spp: a stopped render has at least doubled its samples since
// the last complete pass, and a full render visits each pixel log2(spp / first) + 1 times.
static int plan_passes(int spp, int first, int start[TILES_MAX_PASSES + 1]) {
    int n = 0;
    start[0] = 0;
    long next = first > 1 ? first : 1;
    while (start[n] < spp) {
        start[n + 1] = next < spp ? (int)next : spp;
        n++;
        next *= 2;
    }
    return n;
}

void tiles_init(tiles *t, const int region[4], int spp, int first) {
    memset(t, 0, sizeof *t);
    memcpy(t->region, region, sizeof t->region);
    t->tile_x0 = region[0] / TILES_SIZE;
    t->tile_y0 = region[1] / TILES_SIZE;
    t->tiles_x = (region[2] - 1) / TILES_SIZE - t->tile_x0 + 1;
    t->tile_count = t->tiles_x * ((region[3] - 1) / TILES_SIZE - t->tile_y0 + 1);
    t->pass_count = plan_passes(spp, first, t->pass_start);
    t->spp = spp;
}

static int max_int(int a, int b) { return a > b ? a : b; }
static int min_int(int a, int b) { return a < b ? a : b; }

// Tiles are the cells of the full image's 16x16 grid, clipped to the region: a region's pixels are rendered in
// the same tiles, batches and order as in a full render.
void tiles_rect(const tiles *t, int tile, int r[4]) {
    int cx = (t->tile_x0 + tile % t->tiles_x) * TILES_SIZE, cy = (t->tile_y0 + tile / t->tiles_x) * TILES_SIZE;
    r[0] = max_int(cx, t->region[0]);
    r[1] = max_int(cy, t->region[1]);
    r[2] = min_int(cx + TILES_SIZE, t->region[2]);
    r[3] = min_int(cy + TILES_SIZE, t->region[3]);
}

bool tiles_render_pass(const tiles *t, const integrator *it, int tile, int pass, double *sums, float *means,
                       const atomic_int *stop, thread_stats *ts, _Atomic uint64_t *progress) {
    int r[4];
    tiles_rect(t, tile, r);
    // A film over the caller's arrays, the size of the tile: film_tile_add reads and stores its sums and means
    // exactly as it does in the film of the whole image.
    glint_image img = {.width = r[2] - r[0], .height = r[3] - r[1], .rgb = means, .x0 = r[0], .y0 = r[1]};
    film f = {.image = &img, .sums = sums, .spp = t->spp, .x0 = r[0], .y0 = r[1]};
    tile_pass tp = {.x0 = r[0], .y0 = r[1], .x1 = r[2], .y1 = r[3], .k0 = t->pass_start[pass],
                    .k1 = t->pass_start[pass + 1], .stop = stop};
    film_tile ft;
    film_tile_begin(&ft, &f, tp.x0, tp.y0, tp.x1, tp.y1, tp.k0, tp.k1, ts, progress);
    return it->render_tile(it, &tp, &ft, ts);
}
