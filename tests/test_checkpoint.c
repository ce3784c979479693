// test_checkpoint.c — checkpoints and resumes (render/checkpoint.c, the render loop's counts): a render stopped
// anywhere and resumed, on any thread count, to its spp or a larger one, is bit for bit the uninterrupted render;
// pixels of different counts in one tile (built deterministically from complete renders) resume exactly; regions;
// every mismatched, truncated, corrupt or foreign file is refused with a message naming what is wrong.
#include "glint.h"
#include "check.h"
#include "test_util.h"
#include "film/film.h"
#include "accel/bvh.h"
#include "render/checkpoint.h"
#include "render/frame.h"
#include "render/render.h"
#include "scene/scene.h"

#include <pthread.h>
#include <stdatomic.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

// The ground of the scenes below: a huge sphere, or a quad (which lets the path tracer use its stream loop).
static const char *const GROUND_SPHERE =
    "{\"type\": \"sphere\", \"center\": [0, -100.5, -1], \"radius\": 100, \"material\": \"ground\"}";
static const char *const GROUND_QUAD =
    "{\"type\": \"quad\", \"q\": [-50, -0.5, 50], \"u\": [100, 0, 0], \"v\": [0, 0, -100], \"material\": \"ground\"}";

// A path-traced scene of diffuse, metal and glass spheres on `ground` under a sky; `tail` ends the text (blanks:
// the same scene in another text).
static glint_scene *scene_ground(const char *name, int width, int height, int spp, long long seed, const char *ground,
                                 const char *tail) {
    char text[2048];
    snprintf(text, sizeof text,
             "{\"render\": {\"width\": %d, \"height\": %d, \"spp\": %d, \"seed\": %lld, \"max_depth\": 6,"
             " \"integrator\": \"path\", \"background\": \"sky\"},"
             " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 1, 3], \"lookat\": [0, 0, -1], \"vfov\": 60},"
             " \"materials\": {\"ground\": {\"type\": \"lambertian\", \"albedo\": [0.8, 0.8, 0.0]},"
             "   \"steel\": {\"type\": \"metal\", \"albedo\": [0.7, 0.6, 0.5], \"fuzz\": 0.2},"
             "   \"glass\": {\"type\": \"dielectric\", \"ior\": 1.5}},"
             " \"objects\": [{\"type\": \"sphere\", \"center\": [-1.1, 0, -1], \"radius\": 0.5, \"material\": \"glass\"},"
             "   {\"type\": \"sphere\", \"center\": [1.1, 0, -1], \"radius\": 0.5, \"material\": \"steel\"},"
             "   %s]}%s",
             width, height, spp, seed, ground, tail);
    glint_scene *s = NULL;
    glint_error err;
    if (glint_scene_parse(name, text, strlen(text), &s, &err) != GLINT_OK) fprintf(stderr, "%s\n", err.message);
    return s;
}

static glint_scene *scene_text(const char *name, int width, int height, int spp, long long seed, const char *tail) {
    return scene_ground(name, width, height, spp, seed, GROUND_SPHERE, tail);
}

static glint_scene *scene_with(const char *name, int width, int height, int spp, long long seed) {
    return scene_text(name, width, height, spp, seed, "");
}

static void set_spp(glint_scene *s, int spp) {
    glint_overrides o;
    glint_overrides_init(&o);
    o.spp = spp;
    glint_error err;
    glint_scene_override(s, &o, &err);
}

typedef struct run {
    glint_status status;
    glint_image *image;
    render_stats stats;
    glint_error err;
} run;

// How every render builds its BVH (stream_min_bytes, ...: the tests' knobs); zero: the defaults.
static accel_build_options build_knobs;

static run render_cancel(const glint_scene *s, int threads, const char *checkpoint, const char *resume,
                         const int *region, const atomic_int *cancel) {
    render_options o = {.threads = threads, .checkpoint = checkpoint, .resume = resume, .cancel = cancel,
                        .accel = build_knobs};
    if (region) memcpy(o.region, region, sizeof o.region);
    run r = {0};
    r.status = render_scene(s, &o, NULL, NULL, &r.image, &r.stats, &r.err);
    return r;
}

static run render(const glint_scene *s, int threads, const char *checkpoint, const char *resume, const int *region) {
    return render_cancel(s, threads, checkpoint, resume, region, NULL);
}

static bool same_image(const glint_image *a, const glint_image *b) {
    return a && b && a->width == b->width && a->height == b->height &&
           memcmp(a->rgb, b->rgb, (size_t)a->width * (size_t)a->height * 3 * sizeof(float)) == 0;
}

static bool file_exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

// ---- a render done at one spp, continued to more ----

static void test_complete_and_extended(void) {
    glint_scene *s = scene_with("ext.json", 37, 21, 5, 1);
    run ref5 = render(s, 2, NULL, NULL, NULL);
    run ck = render(s, 2, tmp_path("ext.ckp"), NULL, NULL);
    CHECK(ck.status == GLINT_OK && same_image(ck.image, ref5.image));
    CHECK(ck.stats.spp_done == 5 && ck.stats.samples_resumed == 0);
    // Resumed at the same spp: nothing left to render, the same image.
    run again = render(s, 1, NULL, tmp_path("ext.ckp"), NULL);
    CHECK(again.status == GLINT_OK && same_image(again.image, ref5.image));
    CHECK(again.stats.samples == 0 && again.stats.samples_resumed == 37u * 21u * 5u);
    // Resumed to 13 spp (5 is no pass boundary of 13's plan 0,1,2,4,8,13): the render at 13, bit for bit.
    set_spp(s, 13);
    run ref13 = render(s, 2, NULL, NULL, NULL);
    run more = render(s, 2, tmp_path("ext13.ckp"), tmp_path("ext.ckp"), NULL);
    CHECK(more.status == GLINT_OK && same_image(more.image, ref13.image));
    CHECK(more.stats.samples == 37u * 21u * 8u && more.stats.spp_done == 13);
    // Fewer than the checkpoint holds cannot be: refused, naming --spp.
    set_spp(s, 4);
    run fewer = render(s, 1, NULL, tmp_path("ext13.ckp"), NULL);
    CHECK(fewer.status == GLINT_ERR_INPUT && fewer.image == NULL);
    CHECK(strstr(fewer.err.message, "more than this render's 4; expected --spp 13 or more") != NULL);
    glint_image *images[] = {ref5.image, ck.image, again.image, ref13.image, more.image};
    for (size_t i = 0; i < sizeof images / sizeof images[0]; i++) glint_image_free(images[i]);
    glint_scene_free(s);
}

// ---- pixels of different counts in one tile, built from complete renders ----

// The counts and sums a complete render at `spp` leaves in its checkpoint.
static bool planes_at(glint_scene *s, int spp, const checkpoint_identity *id, uint32_t *counts, double *sums) {
    set_spp(s, spp);
    run r = render(s, 1, tmp_path("part.ckp"), NULL, NULL);
    glint_image_free(r.image);
    checkpoint_plane planes[] = {{"count", CHECKPOINT_U32, 1, counts}, {"rgb", CHECKPOINT_F64, 3, sums}};
    int made_for = 0;
    glint_error err;
    return r.status == GLINT_OK && checkpoint_read(tmp_path("part.ckp"), id, planes, 2, &made_for, &err) == GLINT_OK &&
           made_for == spp;
}

// A sum after k samples does not depend on how passes split them: a checkpoint whose pixels come from complete
// renders at 0, 1, 3, 5 and 8 spp (mixed within every tile) is a valid state, and resumes to the render at 16.
static void test_mixed_counts(void) {
    enum { W = 35, H = 19, N = W * H };
    glint_scene *s = scene_with("mixed.json", W, H, 16, 9);
    int region[4] = {0, 0, W, H};
    checkpoint_identity id;
    glint_error err;
    CHECK(checkpoint_identity_of(s, region, true, &id, &err) == GLINT_OK);
    static const int spps[] = {1, 3, 5, 8};
    static uint32_t counts[5][N], mixed_counts[N];
    static double sums[5][N * 3], mixed_sums[N * 3];
    bool ok = true;
    for (int i = 0; i < 4; i++) ok = ok && planes_at(s, spps[i], &id, counts[i + 1], sums[i + 1]);
    CHECK(ok);
    for (int i = 0; i < N; i++) {
        int pick = (i * 7 + i / W) % 5; // 0: a pixel of no sample yet
        mixed_counts[i] = counts[pick][i];
        memcpy(&mixed_sums[i * 3], &sums[pick][i * 3], 3 * sizeof(double));
    }
    checkpoint_plane planes[] = {{"count", CHECKPOINT_U32, 1, mixed_counts}, {"rgb", CHECKPOINT_F64, 3, mixed_sums}};
    CHECK(checkpoint_write(tmp_path("mixed.ckp"), &id, 8, 0, planes, 2, &err) == GLINT_OK);
    set_spp(s, 16);
    run ref = render(s, 2, NULL, NULL, NULL);
    for (int threads = 1; threads <= 3; threads++) {
        run r = render(s, threads, NULL, tmp_path("mixed.ckp"), NULL);
        CHECK(r.status == GLINT_OK && same_image(r.image, ref.image));
        glint_image_free(r.image);
    }
    // An unknown plane (as AOV sums will be) is skipped; a plane the render needs must be there.
    double extra[N];
    memset(extra, 0, sizeof extra);
    checkpoint_plane more[] = {planes[0], {"albedo", CHECKPOINT_F64, 1, extra}, planes[1]};
    CHECK(checkpoint_write(tmp_path("planes.ckp"), &id, 8, 0, more, 3, &err) == GLINT_OK);
    run r = render(s, 2, NULL, tmp_path("planes.ckp"), NULL);
    CHECK(r.status == GLINT_OK && same_image(r.image, ref.image));
    glint_image_free(r.image);
    CHECK(checkpoint_write(tmp_path("planes.ckp"), &id, 8, 0, planes, 1, &err) == GLINT_OK);
    r = render(s, 2, NULL, tmp_path("planes.ckp"), NULL);
    CHECK(r.status == GLINT_ERR_INPUT && strstr(r.err.message, "no plane \"rgb\"") != NULL);
    glint_image_free(ref.image);
    glint_scene_free(s);
}

// ---- stopped at arbitrary moments, resumed, perhaps stopped again ----

typedef struct stopper {
    double after; ///< seconds
    pthread_t thread;
    atomic_int cancel; ///< the render's token
} stopper;

static void *stop_later(void *arg) {
    const stopper *st = arg; // read-only but for the token
    struct timespec ts = {(time_t)st->after, (long)((st->after - (double)(time_t)st->after) * 1e9)};
    nanosleep(&ts, NULL);
    atomic_store(&((stopper *)arg)->cancel, 1);
    return NULL;
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// Whether some 16x16 tile of the checkpoint holds pixels of different counts (a tile stopped part-way).
static bool has_mixed_tile(const char *path, const checkpoint_identity *id, int w, int h) {
    uint32_t *counts = calloc((size_t)w * (size_t)h, sizeof *counts);
    double *sums = calloc((size_t)w * (size_t)h * 3, sizeof *sums);
    checkpoint_plane planes[] = {{"count", CHECKPOINT_U32, 1, counts}, {"rgb", CHECKPOINT_F64, 3, sums}};
    int spp;
    glint_error err;
    bool mixed = false;
    if (counts && sums && checkpoint_read(path, id, planes, 2, &spp, &err) == GLINT_OK)
        for (int y = 0; y < h && !mixed; y++)
            for (int x = 0; x < w && !mixed; x++)
                mixed = counts[y * w + x] != counts[(y / 16 * 16) * w + x / 16 * 16];
    free(counts);
    free(sums);
    return mixed;
}

// Renders with its token requested `after` seconds from now (a request after the render ended changes nothing).
static run render_stopped(const glint_scene *s, int threads, const char *ckp, const char *resume, const int *region,
                          double after) {
    stopper st = {after, 0, 0};
    pthread_create(&st.thread, NULL, stop_later, &st);
    run r = render_cancel(s, threads, ckp, resume, region, &st.cancel);
    pthread_join(st.thread, NULL);
    return r;
}

// `streams`: the ground is a quad and the path tracer's stream loop is forced (stream_min_bytes), its rays traversed
// together (interleave_min_bytes), so that stops fall inside its window of paths in flight. `noise_threshold` > 0:
// adaptive sampling, whose decisions the checkpoint's odd-numbered samples' sums let a resume make again.
static void test_stopped_and_resumed(bool streams, double noise_threshold) {
    enum { W = 64, H = 48, SPP = 128 };
    glint_scene *s = scene_ground("stop.json", W, H, SPP, 4, streams ? GROUND_QUAD : GROUND_SPHERE, "");
    if (noise_threshold > 0) {
        glint_overrides o;
        glint_overrides_init(&o);
        o.noise_threshold = noise_threshold;
        glint_error err;
        CHECK(glint_scene_override(s, &o, &err) == GLINT_OK);
    }
    build_knobs = (accel_build_options){.stream_min_bytes = streams ? 1 : 0, .interleave_min_bytes = streams ? 1 : 0};
    if (streams) {
        glint_error err;
        accel *a = frame_accel_build(s, &(accel_build_options){.threads = 1, .stream_min_bytes = 1,
                                                               .interleave_min_bytes = 1}, &err);
        CHECK(a && accel_streams(a) == BVH_SIMD && accel_interleaves(a) == BVH_SIMD); // (the SIMD traversal)
        accel_free(a);
    }
    double t0 = now();
    run ref = render(s, 1, NULL, NULL, NULL);
    double full = now() - t0;
    // Adaptive sampling stops pixels before the others: fewer samples than W * H * SPP, yet a complete render.
    CHECK(ref.status == GLINT_OK && ref.stats.spp_done == SPP);
    CHECK(noise_threshold > 0 ? ref.stats.samples < (uint64_t)W * H * SPP : ref.stats.samples == (uint64_t)W * H * SPP);
    int region[4] = {0, 0, W, H};
    checkpoint_identity id;
    glint_error err;
    CHECK(checkpoint_identity_of(s, region, true, &id, &err) == GLINT_OK);
    int interrupted = 0, mixed = 0;
    static const double fractions[] = {0.05, 0.2, 0.45, 0.7};
    for (size_t i = 0; i < sizeof fractions / sizeof fractions[0]; i++) {
        const char *ckp = tmp_path("stop.ckp");
        run a = render_stopped(s, 1, ckp, NULL, NULL, fractions[i] * full);
        if (a.status == GLINT_ERR_INTERRUPTED) interrupted++;
        CHECK(a.status == GLINT_ERR_INTERRUPTED || a.status == GLINT_OK);
        CHECK(file_exists(ckp));
        if (has_mixed_tile(ckp, &id, W, H)) mixed++;
        // Stopped again part-way through the resume (two threads), then resumed on three: still the same.
        run b = render_stopped(s, 2, ckp, ckp, NULL, 0.5 * fractions[i] * full);
        CHECK(b.status == GLINT_ERR_INTERRUPTED || b.status == GLINT_OK);
        if (b.status != GLINT_ERR_INTERRUPTED && b.status != GLINT_OK) fprintf(stderr, "  resume: %s\n", b.err.message);
        run c = render(s, 3, NULL, ckp, NULL);
        CHECK(c.status == GLINT_OK && same_image(c.image, ref.image));
        CHECK(c.stats.samples + c.stats.samples_resumed == ref.stats.samples);
        CHECK(c.stats.spp_done == SPP);
        glint_image_free(a.image);
        glint_image_free(b.image);
        glint_image_free(c.image);
    }
    // On a loaded machine the stopping thread may wake only after a render has ended: stop early a few more times.
    for (int tries = 0; interrupted == 0 && tries < 8; tries++) {
        run a = render_stopped(s, 1, tmp_path("stop.ckp"), NULL, NULL, 0.02 * full);
        if (a.status == GLINT_ERR_INTERRUPTED) interrupted++;
        glint_image_free(a.image);
    }
    CHECK(interrupted > 0);
    if (mixed == 0) printf("note: no stop fell inside a tile this time (test_mixed_counts covers that case)\n");
    build_knobs = (accel_build_options){0};
    glint_image_free(ref.image);
    glint_scene_free(s);
}

// A time limit ends the render after a whole pass and leaves a checkpoint of it, which resumes to the end.
static void test_time_limit(void) {
    glint_scene *s = scene_with("time.json", 40, 24, 9, 5);
    run ref = render(s, 2, NULL, NULL, NULL);
    render_options o = {.threads = 2, .checkpoint = tmp_path("time.ckp"), .time_limit = 1e-9};
    run a = {0};
    a.status = render_scene(s, &o, NULL, NULL, &a.image, &a.stats, &a.err);
    CHECK(a.status == GLINT_OK && a.stats.spp_done == 1);
    o.resume = o.checkpoint; // out of time before its first pass with something to do: as it was
    run b = {0};
    b.status = render_scene(s, &o, NULL, NULL, &b.image, &b.stats, &b.err);
    CHECK(b.status == GLINT_OK && b.stats.spp_done == 1 && b.stats.samples == 0);
    CHECK(b.stats.samples_resumed == 40u * 24u && same_image(a.image, b.image));
    run c = render(s, 1, NULL, tmp_path("time.ckp"), NULL);
    CHECK(c.status == GLINT_OK && same_image(c.image, ref.image) && c.stats.spp_done == 9);
    glint_image *images[] = {ref.image, a.image, b.image, c.image};
    for (size_t i = 0; i < sizeof images / sizeof images[0]; i++) glint_image_free(images[i]);
    glint_scene_free(s);
}

// ---- regions ----

static void test_region(void) {
    glint_scene *s = scene_with("region.json", 50, 40, 2, 2);
    int region[4] = {7, 5, 41, 33};
    run a = render(s, 2, tmp_path("region.ckp"), NULL, region);
    CHECK(a.status == GLINT_OK);
    set_spp(s, 6);
    run ref = render(s, 2, NULL, NULL, region);
    run b = render(s, 1, tmp_path("region.ckp"), tmp_path("region.ckp"), region);
    CHECK(b.status == GLINT_OK && same_image(b.image, ref.image));
    CHECK(b.image && b.image->x0 == 7 && b.image->y0 == 5 && b.image->full_width == 50);
    // Stopped part-way and resumed: the region's pixels of the full render still.
    set_spp(s, 16);
    double t0 = now();
    run ref16 = render(s, 1, NULL, NULL, region);
    run c = render_stopped(s, 1, tmp_path("region.ckp"), tmp_path("region.ckp"), region, 0.3 * (now() - t0));
    run d = render(s, 2, NULL, tmp_path("region.ckp"), region);
    CHECK(d.status == GLINT_OK && same_image(d.image, ref16.image));
    // The whole image, or another region, is another render.
    run whole = render(s, 1, NULL, tmp_path("region.ckp"), NULL);
    CHECK(whole.status == GLINT_ERR_INPUT && strstr(whole.err.message, "with region 7,5,41,33, this render has "
                                                                     "region 0,0,50,40") != NULL);
    glint_image *images[] = {ref.image, a.image, b.image, ref16.image, c.image, d.image};
    for (size_t i = 0; i < sizeof images / sizeof images[0]; i++) glint_image_free(images[i]);
    glint_scene_free(s);
}

// ---- refusals ----

static glint_status resume_with(glint_scene *s, const char *ckp, char *message, size_t size) {
    run r = render(s, 1, NULL, ckp, NULL);
    CHECK(r.image == NULL);
    snprintf(message, size, "%s", r.err.message);
    return r.status;
}

static bool copy_cut(const char *from, const char *to, long keep, long flip) {
    FILE *f = fopen(from, "rb");
    if (!f) return false;
    static unsigned char buf[1 << 20];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    if (keep >= 0 && (size_t)keep < n) n = (size_t)keep;
    if (flip >= 0 && (size_t)flip < n) buf[flip] ^= 0x10;
    return tmp_write(to, buf, n);
}

static void test_refused(void) {
    glint_scene *s = scene_with("a.json", 30, 20, 4, 1);
    run made = render(s, 1, tmp_path("a.ckp"), NULL, NULL);
    CHECK(made.status == GLINT_OK);
    glint_image_free(made.image);
    char msg[1024];
    struct { const char *name; int width, height; long long seed; const char *expect; } others[] = {
        {"a.json", 30, 20, 2, "a.ckp: checkpoint of another render: it was made for a.json with seed 1, this render "
                              "has seed 2; only --spp may change on resuming"},
        {"a.json", 31, 20, 1, "it was made for a.json with size 30x20, this render has size 31x20"},
    };
    for (size_t i = 0; i < sizeof others / sizeof others[0]; i++) {
        glint_scene *o = scene_with(others[i].name, others[i].width, others[i].height, 4, others[i].seed);
        CHECK(resume_with(o, tmp_path("a.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT);
        CHECK(strstr(msg, others[i].expect) != NULL);
        if (!strstr(msg, others[i].expect)) fprintf(stderr, "  got: %s\n", msg);
        glint_scene_free(o);
    }
    // The same settings from another scene text (here one more blank): another scene.
    glint_scene *o = scene_text("b.json", 30, 20, 4, 1, " ");
    glint_error err;
    CHECK(resume_with(o, tmp_path("a.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT);
    CHECK(strstr(msg, "checkpoint of another scene: it was made for a.json, and this render's scene b.json") != NULL);
    glint_scene_free(o);
    // Another depth, accel, encoding, through the command line's overrides.
    glint_overrides ov;
    glint_overrides_init(&ov);
    ov.max_depth = 3;
    glint_scene_override(s, &ov, &err);
    CHECK(resume_with(s, tmp_path("a.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT && strstr(msg, "with depth 6, this "
                                                                                           "render has depth 3"));
    glint_overrides_init(&ov);
    ov.max_depth = 6;
    ov.output_encoding = "linear";
    glint_scene_override(s, &ov, &err);
    CHECK(resume_with(s, tmp_path("a.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "output encoding srgb, this render has output encoding linear"));
    glint_overrides_init(&ov);
    ov.output_encoding = "srgb";
    glint_scene_override(s, &ov, &err);
    run fine = render(s, 1, NULL, tmp_path("a.ckp"), NULL);
    CHECK(fine.status == GLINT_OK);
    glint_image_free(fine.image);

    // Files that are no good checkpoint.
    struct stat st;
    CHECK(stat(tmp_path("a.ckp"), &st) == 0);
    long size = (long)st.st_size;
    struct { long keep, flip; const char *expect; } broken[] = {
        {size - 1, -1, "a.cut: truncated checkpoint: "},
        {100, -1, "a.cut: corrupt checkpoint (truncated header)"},
        {5, -1, "a.cut: not a glint checkpoint (no GLINTCKP signature)"},
        {-1, 40, "a.cut: corrupt checkpoint (header checksum mismatch)"},
        {-1, size - 100, "a.cut: corrupt checkpoint (data checksum mismatch)"},
        {-1, 0, "a.cut: not a glint checkpoint"},
        {-1, 8, "a.cut: checkpoint of format version 18, this glint reads version 2"},
    };
    for (size_t i = 0; i < sizeof broken / sizeof broken[0]; i++) {
        CHECK(copy_cut(tmp_path("a.ckp"), tmp_path("a.cut"), broken[i].keep, broken[i].flip));
        CHECK(resume_with(s, tmp_path("a.cut"), msg, sizeof msg) == GLINT_ERR_INPUT);
        CHECK(strstr(msg, broken[i].expect) != NULL);
        if (!strstr(msg, broken[i].expect)) fprintf(stderr, "  got: %s\n", msg);
    }
    CHECK(tmp_write(tmp_path("garbage.ckp"), "hello, this is not a checkpoint at all\n", 39));
    CHECK(resume_with(s, tmp_path("garbage.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "not a glint checkpoint"));
    CHECK(resume_with(s, tmp_path("missing.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "missing.ckp: cannot open the checkpoint: No such file or directory"));
    CHECK(resume_with(s, tmpdir, msg, sizeof msg) == GLINT_ERR_INPUT && strstr(msg, "Is a directory"));
    // A checkpoint that cannot be written is found before the render, and nothing is left behind.
    CHECK(tmp_write(tmp_path("readonly.ckp"), "x", 1) && chmod(tmp_path("readonly.ckp"), 0444) == 0);
    run ro = render(s, 1, tmp_path("readonly.ckp"), NULL, NULL);
    CHECK(ro.status == GLINT_ERR_RENDER && ro.image == NULL && strstr(ro.err.message, "the file is read-only"));
    run nodir = render(s, 1, tmp_path("nodir/x.ckp"), NULL, NULL);
    CHECK(nodir.status == GLINT_ERR_RENDER && strstr(nodir.err.message, "nodir/x.ckp: cannot write"));
    glint_scene_free(s);
}

// A render stopped before its first sample (here while its BVH is built) still leaves a checkpoint, of no samples,
// from which the whole render resumes.
static void test_stopped_before_build(void) {
    glint_scene *s = scene_with("early.json", 20, 12, 4, 3);
    run ref = render(s, 1, NULL, NULL, NULL);
    atomic_int stop;
    atomic_init(&stop, 1);
    run a = render_cancel(s, 1, tmp_path("early.ckp"), NULL, NULL, &stop);
    CHECK(a.status == GLINT_ERR_INTERRUPTED && file_exists(tmp_path("early.ckp")));
    run b = render(s, 2, NULL, tmp_path("early.ckp"), NULL);
    CHECK(b.status == GLINT_OK && same_image(b.image, ref.image) && b.stats.samples_resumed == 0);
    glint_image_free(ref.image);
    glint_image_free(a.image);
    glint_image_free(b.image);
    glint_scene_free(s);
}

// ---- forged files: valid checksums (anyone can recompute them), contents no render makes ----

// Writes a checkpoint of s's render with the given planes and spp, as a forger would: checkpoint_write computes
// the checksums.
static bool forge(const glint_scene *s, const char *path, int spp, const checkpoint_plane *planes, size_t count,
                  void (*edit)(checkpoint_identity *)) {
    checkpoint_identity id;
    glint_error err;
    int region[4] = {0, 0, s->settings.width, s->settings.height};
    if (checkpoint_identity_of(s, region, true, &id, &err) != GLINT_OK) return false;
    if (edit) edit(&id);
    return checkpoint_write(path, &id, spp, 0, planes, count, &err) == GLINT_OK;
}

static void huge_size(checkpoint_identity *id) {
    id->width = id->height = 2000000000;
    id->region[2] = id->region[3] = 2000000000;
}

static void test_forged(void) {
    enum { W = 6, H = 4, N = W * H };
    glint_scene *s = scene_with("f.json", W, H, 4, 1);
    static uint32_t counts[N], big[N * 64];
    static double sums[N * 3];
    for (int i = 0; i < N; i++) counts[i] = 4;
    for (int i = 0; i < N * 3; i++) sums[i] = 1.0;
    char msg[1024];
    // The same name twice, the second of 64 values a pixel: once a write of 256 bytes a pixel into 4 a pixel.
    checkpoint_plane twice[] = {{"count", CHECKPOINT_U32, 1, counts}, {"count", CHECKPOINT_U32, 64, big},
                                {"rgb", CHECKPOINT_F64, 3, sums}};
    CHECK(forge(s, tmp_path("twice.ckp"), 4, twice, 3, NULL));
    CHECK(resume_with(s, tmp_path("twice.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "corrupt checkpoint (a plane listed twice)"));
    // A plane of the right name and another size is no plane this render can use.
    checkpoint_plane wide[] = {{"count", CHECKPOINT_U32, 64, big}, {"rgb", CHECKPOINT_F64, 3, sums}};
    CHECK(forge(s, tmp_path("wide.ckp"), 4, wide, 2, NULL));
    CHECK(resume_with(s, tmp_path("wide.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "has no plane \"count\" of 1 integer values a pixel"));
    checkpoint_plane good[] = {{"count", CHECKPOINT_U32, 1, counts}, {"rgb", CHECKPOINT_F64, 3, sums}};
    struct { double value; int at; uint32_t count; int spp; const char *expect; } values[] = {
        {NAN, 5, 4, 4, "plane \"rgb\": a sum that is negative, infinite or not a number"},
        {INFINITY, 0, 4, 4, "plane \"rgb\": a sum that is negative, infinite or not a number"},
        {-1.0, 7, 4, 4, "plane \"rgb\": a sum that is negative, infinite or not a number"},
        {1.0, 3, 5, 4, "plane \"count\": a count above the samples per pixel it was made for"},
        {1.0, 3, 0, 4, "pixel 1 has sums but no samples"},
    };
    for (size_t i = 0; i < sizeof values / sizeof values[0]; i++) {
        double keep = sums[values[i].at];
        sums[values[i].at] = values[i].value;
        counts[values[i].at / 3] = values[i].count;
        CHECK(forge(s, tmp_path("values.ckp"), values[i].spp, good, 2, NULL));
        CHECK(resume_with(s, tmp_path("values.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT);
        CHECK(strstr(msg, values[i].expect) != NULL);
        if (!strstr(msg, values[i].expect)) fprintf(stderr, "  got: %s\n", msg);
        sums[values[i].at] = keep;
        counts[values[i].at / 3] = 4;
    }
    // A size no render has: refused before any length is computed from it (it once wrapped around).
    CHECK(forge(s, tmp_path("huge.ckp"), 4, good, 0, huge_size)); // no planes: none could be written
    CHECK(resume_with(s, tmp_path("huge.ckp"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "corrupt checkpoint (header out of range)"));
    // The untouched forgery resumes: the refusals above are the values', not the forging's.
    CHECK(forge(s, tmp_path("fine.ckp"), 4, good, 2, NULL));
    run fine = render(s, 1, NULL, tmp_path("fine.ckp"), NULL);
    CHECK(fine.status == GLINT_OK);
    glint_image_free(fine.image);
    // A FIFO (no writer: opening it would wait for ever) is refused as input and never replaced as output.
    CHECK(mkfifo(tmp_path("c.fifo"), 0600) == 0);
    CHECK(resume_with(s, tmp_path("c.fifo"), msg, sizeof msg) == GLINT_ERR_INPUT &&
          strstr(msg, "c.fifo: cannot open the checkpoint: not a regular file"));
    run out = render(s, 1, tmp_path("c.fifo"), NULL, NULL);
    struct stat st;
    CHECK(out.status == GLINT_ERR_RENDER && strstr(out.err.message, "it is a FIFO, not a regular file"));
    CHECK(stat(tmp_path("c.fifo"), &st) == 0 && S_ISFIFO(st.st_mode));
    unlink(tmp_path("c.fifo"));
    glint_scene_free(s);
}

// A mesh's material library changed after the checkpoint: another scene, though the scene text is the same.
static void test_input_files(void) {
    const char *obj = "mtllib m.mtl\nv 0 0 -1\nv 1 0 -1\nv 0 1 -1\nusemtl red\nf 1 2 3\n";
    const char *mtl1 = "newmtl red\nKd 0.8 0.1 0.1\n", *mtl2 = "newmtl red\nKd 0.1 0.8 0.1\n";
    CHECK(tmp_write(tmp_path("t.obj"), obj, strlen(obj)) && tmp_write(tmp_path("m.mtl"), mtl1, strlen(mtl1)));
    const char *text = "{\"render\": {\"width\": 8, \"height\": 8, \"spp\": 2, \"integrator\": \"path\"},"
                       " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0.3, 0.3, 1], \"lookat\": [0.3, 0.3, -1]},"
                       " \"objects\": [{\"type\": \"mesh\", \"file\": \"t.obj\"}]}";
    glint_scene *s = NULL;
    glint_error err;
    CHECK(glint_scene_parse(tmp_path("mesh.json"), text, strlen(text), &s, &err) == GLINT_OK);
    if (!s) { fprintf(stderr, "%s\n", err.message); return; }
    CHECK(glint_scene_reads_file(s, tmp_path("m.mtl"))); // the library is an input: no image may replace it
    run a = render(s, 1, tmp_path("mesh.ckp"), NULL, NULL);
    CHECK(a.status == GLINT_OK);
    run same = render(s, 1, NULL, tmp_path("mesh.ckp"), NULL);
    CHECK(same.status == GLINT_OK && same_image(same.image, a.image));
    CHECK(tmp_write(tmp_path("m.mtl"), mtl2, strlen(mtl2)));
    run changed = render(s, 1, NULL, tmp_path("mesh.ckp"), NULL);
    CHECK(changed.status == GLINT_ERR_INPUT && strstr(changed.err.message, "checkpoint of another scene"));
    glint_image_free(a.image);
    glint_image_free(same.image);
    glint_scene_free(s);
}

int main(void) {
    if (!tmpdir_make("glint-checkpoint")) return 1;
    test_complete_and_extended();
    test_mixed_counts();
    test_stopped_and_resumed(false, 0);
    test_stopped_and_resumed(true, 0);
    test_stopped_and_resumed(false, 0.05);
    test_time_limit();
    test_region();
    test_refused();
    test_stopped_before_build();
    test_forged();
    test_input_files();
    // Every file a checkpoint write made is in place: no temporary one is left in the directory.
    DIR *d = opendir(tmpdir);
    int temporaries = 0;
    for (struct dirent *e; d && (e = readdir(d));) temporaries += strstr(e->d_name, ".tmp-") != NULL;
    if (d) closedir(d);
    CHECK(temporaries == 0);
    chmod(tmp_path("readonly.ckp"), 0644);
    tmpdir_remove();
    return check_summary();
}
