// test_tiles.c — the work items of a render (render/tiles.h): the full grid's tiles clipped to a region, the
// passes 1, 1, 2, 4, ... (or from 16) and tile passes rendered one by one into caller-given sums, in any order of
// tiles (as glint-mpi's ranks render them), giving the render loop's image bit for bit.
#include "glint.h"
#include "check.h"
#include "film/film.h"
#include "render/frame.h"
#include "render/render.h"
#include "render/tiles.h"
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static glint_scene *load(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/%s", GLINT_SOURCE_DIR, name);
    glint_scene *s = NULL;
    glint_error err;
    if (glint_scene_load(path, &s, &err) != GLINT_OK) {
        fprintf(stderr, "%s\n", err.message);
        exit(1);
    }
    return s;
}

static void test_passes(void) {
    tiles t;
    int whole[4] = {0, 0, 40, 24};
    tiles_init(&t, whole, 1, 1);
    CHECK(t.pass_count == 1 && t.pass_start[0] == 0 && t.pass_start[1] == 1);
    tiles_init(&t, whole, 5, 1);
    CHECK(t.pass_count == 4);
    CHECK(t.pass_start[1] == 1 && t.pass_start[2] == 2 && t.pass_start[3] == 4 && t.pass_start[4] == 5);
    CHECK(tiles_pass_samples(&t, 2) == 2 && tiles_pass_samples(&t, 3) == 1);
    tiles_init(&t, whole, 1000000, 1);
    CHECK(t.pass_count == 21 && t.pass_start[20] == 524288 && t.pass_start[21] == 1000000);
    // A render no one watches: passes from TILES_FIRST_PASS samples, the adaptive sampler's boundaries kept.
    tiles_init(&t, whole, 5, TILES_FIRST_PASS);
    CHECK(t.pass_count == 1 && t.pass_start[1] == 5);
    tiles_init(&t, whole, 16, TILES_FIRST_PASS);
    CHECK(t.pass_count == 1 && t.pass_start[1] == 16);
    tiles_init(&t, whole, 40, TILES_FIRST_PASS);
    CHECK(t.pass_count == 3 && t.pass_start[1] == 16 && t.pass_start[2] == 32 && t.pass_start[3] == 40);
    tiles_init(&t, whole, 1000000, TILES_FIRST_PASS);
    CHECK(t.pass_count == 17 && t.pass_start[16] == 524288 && t.pass_start[17] == 1000000);
    CHECK((int)TILES_FIRST_PASS <= (int)FILM_ADAPTIVE_MIN_SAMPLES && (TILES_FIRST_PASS & (TILES_FIRST_PASS - 1)) == 0);
}

static void test_grid(void) {
    tiles t;
    int region[4] = {5, 3, 37, 29}; // cells 0..2 across, 0..1 down, clipped
    tiles_init(&t, region, 2, 1);
    CHECK(t.tiles_x == 3 && t.tile_count == 6);
    int r[4];
    tiles_rect(&t, 0, r);
    CHECK(r[0] == 5 && r[1] == 3 && r[2] == 16 && r[3] == 16);
    tiles_rect(&t, 4, r);
    CHECK(r[0] == 16 && r[1] == 16 && r[2] == 32 && r[3] == 29);
    tiles_rect(&t, 5, r);
    CHECK(r[0] == 32 && r[1] == 16 && r[2] == 37 && r[3] == 29);

    render_settings rs = {.width = 40, .height = 30};
    glint_error err;
    int out[4];
    CHECK(tiles_resolve_region(&rs, NULL, out, &err) == GLINT_OK && out[2] == 40 && out[3] == 30);
    int empty[4] = {4, 0, 4, 4}, outside[4] = {0, 0, 41, 30};
    CHECK(tiles_resolve_region(&rs, empty, out, &err) == GLINT_ERR_INPUT);
    CHECK(strcmp(err.message, "--region: 4,0,4,4 is empty, expected X0 < X1 and Y0 < Y1") == 0);
    CHECK(tiles_resolve_region(&rs, outside, out, &err) == GLINT_ERR_INPUT && strstr(err.message, "not inside"));
}

// Renders every tile pass of the region with tiles_render_pass, tiles of a pass in reverse order, each pass's
// sums kept per tile as a caller would, and compares every mean with the render loop's image.
static void test_same_as_render_loop(const char *name, const int region[4]) {
    glint_scene *s = load(name);
    s->settings.spp = 6; // one pass in the render loop (TILES_FIRST_PASS), four below
    render_options ro = {.threads = 2};
    if (region) memcpy(ro.region, region, sizeof ro.region);
    glint_image *img = NULL;
    glint_error err;
    CHECK(render_scene(s, &ro, NULL, NULL, &img, NULL, &err) == GLINT_OK);

    int r[4];
    CHECK(tiles_resolve_region(&s->settings, region, r, &err) == GLINT_OK);
    tiles t;
    tiles_init(&t, r, s->settings.spp, 1); // passes of 1, 1, 2, 2; the render loop's one of 6: the same means
    render_frame frame;
    atomic_int stop = 0;
    CHECK(frame_build(&frame, s, NULL, &(accel_build_options){.stop = &stop}, &err) == GLINT_OK);
    double *sums = calloc((size_t)t.tile_count * TILES_SIZE * TILES_SIZE * 3, sizeof *sums);
    float means[TILES_SIZE * TILES_SIZE * 3];
    _Atomic uint64_t progress = 0;
    thread_stats ts = {0};
    int mismatches = 0;
    for (int pass = 0; pass < t.pass_count; pass++)
        for (int tile = t.tile_count - 1; tile >= 0; tile--) {
            double *tile_sums = &sums[(size_t)tile * TILES_SIZE * TILES_SIZE * 3];
            CHECK(tiles_render_pass(&t, frame.integrator, tile, pass, tile_sums, means, &stop, &ts, &progress));
            if (pass + 1 < t.pass_count) continue;
            int tr[4];
            tiles_rect(&t, tile, tr);
            const float *m = means;
            for (int y = tr[1]; y < tr[3]; y++)
                for (int x = tr[0]; x < tr[2]; x++, m += 3) {
                    const float *want = &img->rgb[((size_t)(y - r[1]) * (size_t)img->width + (size_t)(x - r[0])) * 3];
                    mismatches += memcmp(m, want, 3 * sizeof *m) != 0;
                }
        }
    CHECK(mismatches == 0);
    CHECK(ts.samples == (uint64_t)(r[2] - r[0]) * (uint64_t)(r[3] - r[1]) * 6u);
    free(sums);
    frame_release(&frame);
    glint_image_free(img);
    scene_free(s);
}

int main(void) {
    test_passes();
    test_grid();
    test_same_as_render_loop("tiny-path.json", NULL);
    int region[4] = {3, 2, 21, 15};
    test_same_as_render_loop("tiny-path.json", region);
    test_same_as_render_loop("tiny.json", NULL);
    return check_summary();
}
