// test_render.c — the render loop: each pixel is the mean of its samples in index order (bit for bit the
// sequential sum), the same for any thread count; progress reports; a stop keeps completed samples only.
#include "glint.h"
#include "check.h"

#include <pthread.h>
#include <time.h>
#include "integrator/integrator.h"
#include "film/film.h"
#include "render/frame.h"
#include "scene/scene.h"

#include <stdlib.h>
#include <string.h>

// A small scene of the kind the integrator names: coloured spheres under point and ambient light
// (Whitted, colour mode) or diffuse, metal and glass spheres under a sky (path tracer).
static glint_scene *make_scene(integrator_kind kind, int width, int height, int spp) {
    glint_scene *s = scene_new("test");
    render_settings *rs = &s->settings;
    rs->width = width;
    rs->height = height;
    rs->spp = spp;
    rs->seed = 7;
    rs->integrator = kind;
    rs->max_depth = kind == INTEGRATOR_PATH ? 8 : 3;
    rs->transform = TRANSFORM_GAMMA2;
    s->camera.lookfrom = v3(0, 1, 3);
    s->camera.lookat = v3(0, 0, -1);
    s->camera.vfov_degrees = 60.0f;
    material m[4];
    if (kind == INTEGRATOR_PATH) {
        rs->background = BACKGROUND_SKY;
        m[0] = material_default(MAT_LAMBERTIAN);
        m[1] = material_default(MAT_METAL);
        m[1].fuzz = 0.2f;
        m[2] = material_default(MAT_DIELECTRIC);
        m[3] = material_default(MAT_LAMBERTIAN);
        m[3].albedo = v3(0.8f, 0.8f, 0.0f);
    } else {
        rs->background_color = v3(0.2f, 0.3f, 0.5f);
        for (int i = 0; i < 4; i++) {
            m[i] = material_default(MAT_PHONG);
            m[i].specular = 50 * (i + 1);
            m[i].reflective = 0.1f * (float)i;
        }
        m[0].albedo = v3(1, 0, 0);
        m[1].albedo = v3(0, 1, 0);
        m[2].albedo = v3(0, 0, 1);
        m[3].albedo = v3(1, 1, 0);
        light l = {.kind = LIGHT_AMBIENT, .intensity = v3s(0.2f)};
        scene_add_light(s, l);
        l = (light){.kind = LIGHT_POINT, .intensity = v3s(0.6f), .position = v3(2, 3, 1)};
        scene_add_light(s, l);
    }
    for (int i = 0; i < 4; i++) scene_add_material(s, &m[i], NULL);
    scene_add_sphere(s, (sphere){v3(-1.1f, 0, -1), 0.5f, 0});
    scene_add_sphere(s, (sphere){v3(0, 0, -1), 0.5f, 1});
    scene_add_sphere(s, (sphere){v3(1.1f, 0, -1), 0.5f, 2});
    scene_add_sphere(s, (sphere){v3(0, -100.5f, -1), 100.0f, 3});
    return s;
}

// Mean of samples 0..n-1 of pixel (x, y), accumulated exactly as the contract says.
static void reference_pixel(const integrator *it, int x, int y, int n, float out[3]) {
    const glint_scene *s = it->scene;
    uint64_t pixel = (uint64_t)y * (uint64_t)s->settings.width + (uint64_t)x;
    thread_stats ts = {0};
    double sum[3] = {0, 0, 0};
    for (int k = 0; k < n; k++) {
        rng r = rng_for_stream(it->stream, rng_pixel_key(s->settings.seed, pixel), (uint64_t)k);
        vec3 c = it->sample(it, x, y, (uint32_t)k, &r, &ts, NULL);
        if (!v3_is_finite(c)) continue;
        sum[0] += c.x;
        sum[1] += c.y;
        sum[2] += c.z;
    }
    for (int c = 0; c < 3; c++) out[c] = (float)(sum[c] / n);
}

static glint_image *render_with(glint_scene *s, int threads, glint_cancel *cancel, glint_status *st,
                                glint_render_stats *stats) {
    glint_render_options opt = {.threads = threads, .cancel = cancel};
    glint_image *img = NULL;
    glint_error err;
    *st = glint_render(s, &opt, NULL, NULL, &img, stats, &err);
    return img;
}

static glint_image *render(glint_scene *s, int threads, glint_status *st, glint_render_stats *stats) {
    return render_with(s, threads, NULL, st, stats);
}

// Bit-identical images for 1..5 threads, each pixel exactly the sequential mean; sizes that are not
// multiples of the tile, and an image of a single tile rendered by more threads than tiles (each pass then
// waits for the previous one).
static void test_deterministic(integrator_kind kind, int width, int height, int spp) {
    glint_scene *s = make_scene(kind, width, height, spp);
    glint_status st;
    glint_render_stats stats;
    glint_image *first = render(s, 1, &st, &stats);
    CHECK(st == GLINT_OK && first != NULL);
    if (!first) { glint_scene_free(s); return; }
    CHECK(stats.samples == (uint64_t)width * (uint64_t)height * (uint64_t)spp);
    CHECK(stats.threads == 1);
    render_frame frame;
    glint_error err;
    CHECK(frame_build(&frame, s, NULL, NULL, &err) == GLINT_OK);
    int mismatches = 0;
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            float want[3];
            reference_pixel(frame.integrator, x, y, spp, want);
            if (memcmp(want, &first->rgb[((size_t)y * (size_t)width + (size_t)x) * 3], sizeof want) != 0)
                mismatches++;
        }
    CHECK(mismatches == 0);
    frame_release(&frame);
    size_t bytes = (size_t)width * (size_t)height * 3 * sizeof(float);
    for (int threads = 2; threads <= 5; threads++) {
        glint_image *img = render(s, threads, &st, &stats);
        CHECK(st == GLINT_OK && img != NULL);
        CHECK(stats.threads == threads);
        CHECK(img && memcmp(img->rgb, first->rgb, bytes) == 0);
        glint_image_free(img);
    }
    glint_image_free(first);
    glint_scene_free(s);
}

typedef struct progress_log {
    int calls;
    double last;
    bool monotonic, in_range;
    glint_cancel *stop_at_first; ///< requested from the first report (NULL: none)
} progress_log;

static void on_progress(double fraction, void *user) {
    progress_log *log = user;
    if (fraction < log->last) log->monotonic = false;
    if (!(fraction >= 0.0 && fraction <= 1.0)) log->in_range = false;
    log->last = fraction;
    log->calls++;
    if (log->stop_at_first) glint_cancel_request(log->stop_at_first);
}

static void test_progress(void) {
    glint_scene *s = make_scene(INTEGRATOR_WHITTED, 40, 30, 4);
    progress_log log = {.monotonic = true, .in_range = true};
    glint_render_options opt = {.threads = 2};
    glint_image *img = NULL;
    glint_render_stats stats;
    glint_error err;
    CHECK(glint_render(s, &opt, on_progress, &log, &img, &stats, &err) == GLINT_OK);
    CHECK(log.calls >= 1 && log.monotonic && log.in_range);
    CHECK(log.last == 1.0); // the last report says done
    glint_image_free(img);
    glint_scene_free(s);
}

// A token requested before the render: nothing is rendered, the image is black; reset, it lets the next render
// run to the end.
static void test_stop_before(void) {
    glint_scene *s = make_scene(INTEGRATOR_WHITTED, 20, 10, 2);
    glint_cancel *cancel = glint_cancel_new();
    glint_cancel_request(cancel);
    CHECK(glint_cancel_requested(cancel));
    glint_status st;
    glint_render_stats stats;
    glint_image *img = render_with(s, 2, cancel, &st, &stats);
    CHECK(st == GLINT_ERR_INTERRUPTED);
    CHECK(stats.samples == 0);
    int nonzero = 0;
    for (size_t i = 0; img && i < 20 * 10 * 3; i++) nonzero += img->rgb[i] != 0.0f;
    CHECK(img != NULL && nonzero == 0);
    glint_image_free(img);
    glint_cancel_reset(cancel);
    img = render_with(s, 2, cancel, &st, &stats);
    CHECK(st == GLINT_OK && stats.samples == 20 * 10 * 2);
    glint_image_free(img);
    glint_cancel_free(cancel);
    glint_scene_free(s);
}

// A stop in the middle of a long render (from the first progress report): every pixel holds the mean of
// its first k samples for some k, never a sum divided by spp, never a mix.
static void test_stop_during(void) {
    enum { SW = 6, SH = 5, SPP = 400000 };
    glint_scene *s = make_scene(INTEGRATOR_PATH, SW, SH, SPP);
    glint_cancel *cancel = glint_cancel_new();
    progress_log log = {.monotonic = true, .in_range = true, .stop_at_first = cancel};
    glint_render_options opt = {.threads = 2, .cancel = cancel};
    glint_image *img = NULL;
    glint_render_stats stats;
    glint_error err;
    glint_status st = glint_render(s, &opt, on_progress, &log, &img, &stats, &err);
    // Only a machine that renders 12 million path samples within the first report could finish.
    CHECK(st == GLINT_ERR_INTERRUPTED || st == GLINT_OK);
    CHECK(img != NULL);
    if (!img) { glint_scene_free(s); return; }
    if (st == GLINT_ERR_INTERRUPTED) CHECK(stats.samples < (uint64_t)SW * SH * SPP);
    render_frame frame;
    CHECK(frame_build(&frame, s, NULL, NULL, &err) == GLINT_OK);
    const integrator *it = frame.integrator;
    int inconsistent = 0;
    uint64_t matched_samples = 0;
    for (int y = 0; y < SH; y++)
        for (int x = 0; x < SW; x++) {
            const float *got = &img->rgb[((size_t)y * SW + (size_t)x) * 3];
            uint64_t pixel = (uint64_t)y * SW + (uint64_t)x;
            thread_stats ts = {0};
            double sum[3] = {0, 0, 0};
            // Walk the running mean until it equals the pixel: k = 0 is a black pixel.
            bool found = got[0] == 0.0f && got[1] == 0.0f && got[2] == 0.0f;
            for (int k = 0; !found && k < SPP; k++) {
                rng r = rng_for_stream(it->stream, rng_pixel_key(s->settings.seed, pixel), (uint64_t)k);
                vec3 c = it->sample(it, x, y, (uint32_t)k, &r, &ts, NULL);
                if (v3_is_finite(c)) {
                    sum[0] += c.x;
                    sum[1] += c.y;
                    sum[2] += c.z;
                }
                float mean[3];
                for (int i = 0; i < 3; i++) mean[i] = (float)(sum[i] / (k + 1));
                if (memcmp(mean, got, sizeof mean) == 0) {
                    found = true;
                    matched_samples += (uint64_t)k + 1;
                }
            }
            if (!found) inconsistent++;
        }
    printf("stop during the render: %s after %llu samples, pixels hold %llu\n",
           st == GLINT_OK ? "finished" : "stopped", (unsigned long long)stats.samples,
           (unsigned long long)matched_samples);
    CHECK(inconsistent == 0);
    CHECK(matched_samples <= stats.samples); // no pixel claims samples that were not rendered
    frame_release(&frame);
    glint_image_free(img);
    glint_cancel_free(cancel);
    glint_scene_free(s);
}

// Two renders in one process, on two threads, each with its own token: cancelling one leaves the other's image
// byte for byte that of a render nobody cancelled.
typedef struct side_render {
    const glint_scene *scene;
    glint_cancel *cancel;
    glint_image *image;
    glint_status status;
    pthread_t thread;
} side_render;

static void *side_main(void *arg) {
    side_render *r = arg;
    glint_render_options opt = {.threads = 1, .cancel = r->cancel};
    glint_render_stats stats;
    glint_error err;
    r->status = glint_render(r->scene, &opt, NULL, NULL, &r->image, &stats, &err);
    return NULL;
}

static void test_two_tokens(void) {
    enum { TW = 24, TH = 16, TSPP = 600 };
    glint_scene *s = make_scene(INTEGRATOR_PATH, TW, TH, TSPP);
    glint_status st;
    glint_render_stats stats;
    glint_image *reference = render(s, 1, &st, &stats);
    CHECK(st == GLINT_OK && reference);
    side_render a = {s, glint_cancel_new(), NULL, GLINT_OK, 0}, b = {s, glint_cancel_new(), NULL, GLINT_OK, 0};
    CHECK(pthread_create(&a.thread, NULL, side_main, &a) == 0 && pthread_create(&b.thread, NULL, side_main, &b) == 0);
    struct timespec pause = {0, 20 * 1000 * 1000};
    nanosleep(&pause, NULL);
    glint_cancel_request(a.cancel);
    pthread_join(a.thread, NULL);
    pthread_join(b.thread, NULL);
    CHECK(a.status == GLINT_ERR_INTERRUPTED && a.image); // 20 ms are far from 230,000 path samples
    CHECK(b.status == GLINT_OK && b.image && !glint_cancel_requested(b.cancel));
    CHECK(reference && b.image && memcmp(reference->rgb, b.image->rgb, (size_t)TW * TH * 3 * sizeof(float)) == 0);
    glint_image_free(a.image);
    glint_image_free(b.image);
    glint_image_free(reference);
    glint_cancel_free(a.cancel);
    glint_cancel_free(b.cancel);
    glint_scene_free(s);
}

// The scene is plain data and every render builds its own frame: overrides made after a render (size,
// structure, samples) take effect in the next one, and the scene itself is left as it was.
static void test_override_after_render(void) {
    glint_scene *s = make_scene(INTEGRATOR_PATH, 16, 8, 2);
    glint_status st;
    glint_render_stats stats;
    glint_image *first = render(s, 1, &st, &stats);
    CHECK(st == GLINT_OK && stats.bvh_leaves > 0);
    glint_scene before = *s;
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = 24;
    o.spp = 3;
    o.accel = "none";
    glint_error err;
    CHECK(glint_scene_override(s, &o, &err) == GLINT_OK);
    glint_image *second = render(s, 1, &st, &stats);
    int w = 0, h = 0;
    const float *rgb;
    if (second) glint_image_info(second, &w, &h, &rgb);
    CHECK(st == GLINT_OK && w == 24 && h == 8);
    CHECK(stats.samples == 24 * 8 * 3);
    CHECK(stats.bvh_nodes == 0 && stats.bvh_leaves == 0); // brute force: the new structure was built
    // Rendering read the scene and wrote nothing into it (the camera, too, is prepared in the frame).
    CHECK(memcmp(&before.camera, &s->camera, sizeof before.camera) == 0);
    glint_image_free(first);
    glint_image_free(second);
    glint_scene_free(s);
}

// A stop requested while the BVH is built ends the build (a large scene must not keep a stopped program
// busy), says so, and leaves nothing behind; without the request the same scene builds.
static void test_stop_during_build(void) {
    glint_scene *s = make_scene(INTEGRATOR_PATH, 8, 8, 1);
    for (int i = 0; i < 20000; i++)
        scene_add_sphere(s, (sphere){v3((float)(i % 100), (float)(i / 100 % 100), (float)(i / 10000) - 5.0f), 0.3f, 0});
    atomic_int stop;
    atomic_init(&stop, 1);
    render_frame frame;
    glint_error err;
    CHECK(frame_build(&frame, s, NULL, &(accel_build_options){.stop = &stop}, &err) == GLINT_ERR_INTERRUPTED);
    CHECK(strcmp(err.message, "interrupted while building the BVH") == 0);
    CHECK(frame.accel == NULL && frame.integrator == NULL);
    atomic_store(&stop, 0);
    CHECK(frame_build(&frame, s, NULL, &(accel_build_options){.stop = &stop}, &err) == GLINT_OK);
    frame_release(&frame);
    glint_scene_free(s);
}

// A time limit ends the render after a whole sample pass: with a limit too short for anything but the first
// pass, the image is exactly that of a 1-spp render, with GLINT_OK; a limit never reached changes nothing.
static void test_time_limit(void) {
    glint_scene *s = make_scene(INTEGRATOR_PATH, 21, 13, 8);
    glint_error err;
    glint_image *full = NULL, *cut = NULL, *one = NULL, *slow = NULL;
    glint_render_stats st;
    glint_render_options opt = {.threads = 2};
    CHECK(glint_render(s, &opt, NULL, NULL, &full, &st, &err) == GLINT_OK && st.spp_done == 8);
    opt.time_limit = 1e-9;
    CHECK(glint_render(s, &opt, NULL, NULL, &cut, &st, &err) == GLINT_OK);
    CHECK(st.spp_done == 1 && st.samples == 21 * 13);
    opt.time_limit = 1e6;
    CHECK(glint_render(s, &opt, NULL, NULL, &slow, &st, &err) == GLINT_OK && st.spp_done == 8);
    s->settings.spp = 1;
    opt.time_limit = 0.0;
    CHECK(glint_render(s, &opt, NULL, NULL, &one, &st, &err) == GLINT_OK);
    size_t bytes = 21 * 13 * 3 * sizeof(float);
    CHECK(cut && one && memcmp(cut->rgb, one->rgb, bytes) == 0);
    CHECK(slow && full && memcmp(slow->rgb, full->rgb, bytes) == 0);
    glint_image_free(full);
    glint_image_free(cut);
    glint_image_free(one);
    glint_image_free(slow);
    glint_scene_free(s);
}

int main(void) {
    test_time_limit();
    test_stop_during_build();
    test_override_after_render();
    test_deterministic(INTEGRATOR_WHITTED, 37, 21, 1);
    test_deterministic(INTEGRATOR_WHITTED, 37, 21, 5);
    test_deterministic(INTEGRATOR_PATH, 35, 18, 6);
    test_deterministic(INTEGRATOR_PATH, 5, 3, 9); // one tile, four passes, up to five threads
    test_progress();
    test_stop_before();
    test_stop_during();
    test_two_tokens();
    return check_summary();
}
