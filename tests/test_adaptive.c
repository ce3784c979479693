// test_adaptive.c — adaptive sampling ("noise_threshold"): pixels converge and stop, each pixel is exactly the mean of
// its first n samples (n its sample-count AOV), and n is what the documented rule gives when the samples are replayed
// one by one (stopped at the first power of two >= 16 whose half-buffer error is below the threshold, else spp); the
// same bytes for any thread count; a checkpoint resumed to a larger spp is the render made at that spp at once.
#include "check.h"
#include "test_load.h"
#include "glint.h"
#include "test_util.h"
#include "film/film.h"
#include "integrator/integrator_common.h"
#include "render/frame.h"
#include "render/render.h"
#include "scene/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 24, H = 16, SPP = 64 };
static const double THRESHOLD = 0.05;

static glint_scene *load(int spp, const char *sampler) {
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = W;
    o.height = H;
    o.spp = spp;
    o.sampler = sampler;
    o.noise_threshold = THRESHOLD;
    glint_scene *s = test_load(test_data_path("tiny-path.json"), &o);
    CHECK(s != NULL);
    return s;
}

static glint_image *render(const glint_scene *s, int threads, const char *checkpoint, const char *resume) {
    render_options opt = {.threads = threads, .aovs = checkpoint || resume ? 0u : GLINT_AOV_SAMPLES,
                          .checkpoint = checkpoint, .resume = resume};
    glint_image *img = NULL;
    glint_error err;
    glint_status st = render_scene(s, &opt, NULL, NULL, &img, NULL, &err);
    if (st != GLINT_OK) fprintf(stderr, "render: %s\n", err.message);
    CHECK(st == GLINT_OK && img);
    return img;
}

// The documented error of a pixel after n samples whose sums (all, odd-numbered) are sum and odd.
static double error_of(const double sum[3], const double odd[3], int n) {
    double difference = 0.0, brightness = 0.0;
    for (int c = 0; c < 3; c++) {
        difference += fabs((sum[c] - odd[c]) - odd[c]) / (n / 2.0);
        brightness += sum[c] / n;
    }
    return 0.5 * difference / (1e-4 + sqrt(brightness > 0 ? brightness : 0));
}

// Replays every pixel's samples and checks its count and value against the rule.
static void test_rule(const char *sampler) {
    glint_scene *s = load(SPP, sampler);
    if (!s) return;
    glint_image *img = render(s, 2, NULL, NULL);
    const float *counts = img ? glint_image_aov(img, GLINT_AOV_SAMPLES, NULL) : NULL;
    CHECK(counts != NULL);
    render_frame frame;
    glint_error err;
    CHECK(frame_build(&frame, s, NULL, NULL, &err) == GLINT_OK);
    const integrator *it = frame.integrator;
    int stopped = 0, full = 0, wrong_count = 0, wrong_value = 0;
    for (int y = 0; counts && y < H; y++)
        for (int x = 0; x < W; x++) {
            uint64_t key = rng_pixel_key(s->settings.seed, (uint64_t)y * W + (uint64_t)x);
            thread_stats ts = {0};
            double sum[3] = {0, 0, 0}, odd[3] = {0, 0, 0};
            int n = SPP;
            for (int k = 0; k < SPP; k++) {
                rng r = rng_for_stream(it->stream, key, (uint64_t)k);
                vec3 c = it->sample(it, x, y, (uint32_t)k, &r, &ts, NULL);
                if (v3_is_finite(c)) {
                    double v[3] = {c.x, c.y, c.z};
                    for (int ch = 0; ch < 3; ch++) {
                        sum[ch] += v[ch];
                        if (k & 1) odd[ch] += v[ch];
                    }
                }
                int taken = k + 1;
                if (taken >= FILM_ADAPTIVE_MIN_SAMPLES && (taken & (taken - 1)) == 0 && taken < SPP &&
                    error_of(sum, odd, taken) < THRESHOLD) {
                    n = taken;
                    break;
                }
            }
            size_t i = (size_t)y * W + (size_t)x;
            wrong_count += counts[i] != (float)n;
            double inv = 1.0 / n; // as film_store_mean divides
            for (int ch = 0; ch < 3; ch++) wrong_value += img->rgb[i * 3 + (size_t)ch] != (float)(sum[ch] * inv);
            stopped += n < SPP;
            full += n == SPP;
        }
    printf("%s: %d pixels stopped before %d samples, %d took them all\n", sampler, stopped, SPP, full);
    CHECK(wrong_count == 0 && wrong_value == 0);
    CHECK(stopped > 0 && full > 0); // the test's threshold separates the scene's smooth pixels from its noisy ones
    frame_release(&frame);
    // Any thread count: the same bytes, counts included.
    glint_image *one = render(s, 1, NULL, NULL), *three = render(s, 3, NULL, NULL);
    size_t n = (size_t)W * H;
    CHECK(img && one && three && memcmp(img->rgb, one->rgb, n * 3 * sizeof(float)) == 0 &&
          memcmp(img->rgb, three->rgb, n * 3 * sizeof(float)) == 0);
    const float *c1 = one ? glint_image_aov(one, GLINT_AOV_SAMPLES, NULL) : NULL;
    CHECK(counts && c1 && memcmp(counts, c1, n * sizeof(float)) == 0);
    glint_image_free(one);
    glint_image_free(three);
    glint_image_free(img);
    glint_scene_free(s);
}

// A render at 32 spp kept in a checkpoint, resumed to 64: the 64-spp render, bit for bit (its converged pixels
// stay stopped, the others go on from their sums).
static void test_resume_to_more(const char *sampler) {
    glint_scene *s32 = load(32, sampler), *s64 = load(SPP, sampler);
    if (!s32 || !s64) return;
    glint_image *ref = render(s64, 2, NULL, NULL);
    glint_image *part = render(s32, 2, tmp_path("a.ckp"), NULL);
    glint_image *more = render(s64, 3, NULL, tmp_path("a.ckp"));
    CHECK(ref && more && memcmp(ref->rgb, more->rgb, (size_t)W * H * 3 * sizeof(float)) == 0);
    glint_image_free(ref);
    glint_image_free(part);
    glint_image_free(more);
    glint_scene_free(s32);
    glint_scene_free(s64);
}

int main(void) {
    if (!tmpdir_make("glint-adaptive")) return 1;
    test_rule("sobol");
    test_rule("independent");
    test_resume_to_more("sobol");
    test_resume_to_more("independent");
    tmpdir_remove();
    return check_summary();
}
