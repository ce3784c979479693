// test_camera_batch.c — the render loop's camera rays made eight at a time are, lane for lane and bit for bit,
// the rays and generators that rng_for_stream and camera_sample_ray make one at a time: with and without
// defocus blur, with and without an open shutter (the ray's time), for the look-at and the viewport camera, for
// any pixel and sample index, with PCG32 and with the Sobol' sampler.
#include "glint.h"
#include "check.h"
#include "camera/camera_batch.h"
#include "scene/scene.h"

#include <string.h>

// A path-tracer scene of the given camera, prepared for a 640x360 image.
static glint_scene *make_scene(camera_kind kind, float defocus_degrees) {
    glint_scene *s = scene_new("camera-batch");
    s->settings.width = 640;
    s->settings.height = 360;
    s->settings.integrator = INTEGRATOR_PATH;
    s->camera.kind = kind;
    s->camera.lookfrom = v3(13, 2, 3);
    s->camera.lookat = v3(0, 0, 0);
    s->camera.vfov_degrees = 20.0f;
    s->camera.defocus_angle_degrees = defocus_degrees;
    s->camera.focus_distance = 10.0f;
    s->camera.position[0] = 0.5;
    s->camera.position[1] = -0.25;
    s->camera.viewport_width = 1.6;
    s->camera.viewport_height = 0.9;
    s->camera.distance = 1.0;
    camera_prepare(&s->camera, s->settings.width, s->settings.height);
    return s;
}

// Fills a batch with pseudo-random pixels and sample indices (some lanes repeated, as at a tile's end) and
// checks every lane against the one-at-a-time code, on a PCG32 stream and with the Sobol' sampler.
static void check_batches_on(const glint_scene *s, const char *what, uint64_t stream) {
    uint64_t lcg = 0x9e3779b97f4a7c15ULL;
    int mismatches = 0;
    for (int round = 0; round < 200; round++) {
        camera_batch b;
        for (int i = 0; i < CAMERA_BATCH; i++) {
            lcg = lcg * 6364136223846793005ULL + 1442695040888963407ULL;
            b.x[i] = (int)((lcg >> 33) % (uint64_t)s->settings.width);
            b.y[i] = (int)((lcg >> 13) % (uint64_t)s->settings.height);
            b.sample[i] = (lcg >> 50) % 1000u;
            if (round % 7 == 0 && i >= 5) b.x[i] = b.x[0], b.y[i] = b.y[0], b.sample[i] = b.sample[0];
            b.key[i] = rng_pixel_key(12345, (uint64_t)b.y[i] * (uint64_t)s->settings.width + (uint64_t)b.x[i]);
        }
        camera_batch_make(&s->camera, stream, &b);
        for (int i = 0; i < CAMERA_BATCH; i++) {
            rng r = rng_for_stream(stream, b.key[i], b.sample[i]);
            ray want = camera_sample_ray(&s->camera, b.x[i], b.y[i], &r);
            bool same = memcmp(&want.o, &b.o[i], sizeof want.o) == 0 && memcmp(&want.d, &b.d[i], sizeof want.d) == 0 &&
                        memcmp(&want.time, &b.time[i], sizeof want.time) == 0 && r.state == b.r[i].state &&
                        r.inc == b.r[i].inc;
            mismatches += !same;
        }
    }
    if (mismatches)
        fprintf(stderr, "%s (%s): %d of %d lanes differ\n", what, stream == RNG_SOBOL_STREAM ? "sobol" : "pcg32",
                mismatches, 200 * CAMERA_BATCH);
    CHECK(mismatches == 0);
}

static void check_batches(const glint_scene *s, const char *what) {
    check_batches_on(s, what, rng_seed_stream(12345));
    check_batches_on(s, what, RNG_SOBOL_STREAM);
}

int main(void) {
    glint_scene *s = make_scene(CAMERA_LOOKAT, 0.6f);
    check_batches(s, "look-at with defocus blur");
    glint_scene_free(s);
    s = make_scene(CAMERA_LOOKAT, 0.0f);
    check_batches(s, "look-at, pinhole");
    glint_scene_free(s);
    s = make_scene(CAMERA_VIEWPORT, 0.0f);
    check_batches(s, "viewport");
    glint_scene_free(s);
    // An open shutter draws each ray's time after the camera's other draws; a closed one draws nothing.
    s = make_scene(CAMERA_LOOKAT, 0.6f);
    s->camera.shutter_open = 0.25f;
    s->camera.shutter_close = 0.75f;
    check_batches(s, "look-at with defocus blur and an open shutter");
    s->camera.shutter_close = 0.25f;
    check_batches(s, "look-at with defocus blur and a closed shutter at 0.25");
    glint_scene_free(s);
    s = make_scene(CAMERA_VIEWPORT, 0.0f);
    s->camera.shutter_close = 1.0f;
    check_batches(s, "viewport with an open shutter");
    glint_scene_free(s);
    return check_summary();
}
