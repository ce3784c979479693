// test_trace.c — the trace recorder: JSON strings for any bytes, lanes that grow and are filled by threads at
// once, copied text arguments, the file's shape; and a traced render through the public API: one "tile" event per
// tile and pass on the workers' rows, the same pixels as without a trace, a write that fails leaving no file.
#include "check.h"
#include "core/trace.h"
#include "glint.h"
#include "test_util.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// What trace_json_string writes for s.
static char *json_of(const char *s) {
    char *buf = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&buf, &n);
    if (!f) return NULL;
    trace_json_string(f, s);
    fclose(f);
    return buf;
}

static void check_json(const char *s, const char *expected) {
    char *got = json_of(s);
    CHECK(got && strcmp(got, expected) == 0);
    if (got && strcmp(got, expected) != 0) fprintf(stderr, "  got %s, expected %s\n", got, expected);
    free(got);
}

static void test_json_strings(void) {
    check_json("tile", "\"tile\"");
    check_json("", "\"\"");
    check_json("a \"quoted\" \\ name", "\"a \\\"quoted\\\" \\\\ name\"");
    check_json("tab\there\nline\x01\x1f", "\"tab\\u0009here\\u000aline\\u0001\\u001f\"");
    check_json("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80", "\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\""); // é € 😀
    check_json("\x7f", "\"\x7f\""); // DEL needs no escape in JSON
    // Bytes that are not UTF-8 become U+FFFD, one for each byte of a broken sequence.
    check_json("a\xff" "b", "\"a\\ufffdb\"");
    check_json("\xc0\x80", "\"\\ufffd\\ufffd\"");             // an overlong NUL
    check_json("\xed\xa0\x80", "\"\\ufffd\\ufffd\\ufffd\""); // a UTF-16 surrogate
    check_json("\xf4\x90\x80\x80", "\"\\ufffd\\ufffd\\ufffd\\ufffd\""); // past U+10FFFF
    check_json("\xe2\x82", "\"\\ufffd\\ufffd\"");             // cut short by the end of the string
    check_json("\xe2\x82x", "\"\\ufffd\\ufffdx\"");           // cut short by an ASCII byte
}

// The whole trace as JSON text (malloc'd).
static char *trace_text(const trace *t) {
    char *buf = NULL;
    size_t n = 0;
    FILE *f = open_memstream(&buf, &n);
    if (!f) return NULL;
    CHECK(trace_write_json(t, f) == 0);
    fclose(f);
    return buf;
}

static size_t count_of(const char *text, const char *what) {
    size_t n = 0;
    for (const char *p = text; p && (p = strstr(p, what)); p += strlen(what)) n++;
    return n;
}

static void test_lane_growth_and_file(void) {
    trace *t = trace_new();
    CHECK(t != NULL);
    if (!t) return;
    trace_lane *a = trace_lane_open(t, "main"), *b = trace_lane_open(t, "worker \"1\"");
    CHECK(a && b && trace_lane_owner(a) == t);
    if (!a || !b) return;
    // Far past the first allocation: the lane doubles as often as needed and keeps every event.
    int64_t t0 = trace_clock();
    for (int i = 0; i < 5000; i++)
        trace_add(a, &(trace_event){"tile", "render", t0 + i, t0 + i + 1500, 2, {{"x", i, NULL}, {"pass", -i, NULL}}});
    char path[] = "dir/\"odd\"\tname";
    trace_add(b, &(trace_event){"image write", "io", t0, t0 + 2000, 1, {{"file", 0, path}}});
    path[0] = 'X'; // the lane keeps a copy of the text, not the caller's buffer
    // An end before the start is a duration of 0, never negative.
    trace_add(b, &(trace_event){"backwards", "io", t0 + 10, t0, 0, {{0}}});
    CHECK(trace_event_count(t) == 5002);
    CHECK(trace_complete(t));
    char *text = trace_text(t);
    CHECK(text != NULL);
    CHECK(strncmp(text, "{\"traceEvents\":[\n", 17) == 0);
    CHECK(strstr(text, "\n],\n\"displayTimeUnit\":\"ms\"}\n") != NULL);
    CHECK(count_of(text, "\"name\":\"tile\",\"cat\":\"render\",\"ph\":\"X\"") == 5000);
    CHECK(count_of(text, "\"name\":\"thread_name\",\"ph\":\"M\"") == 2);
    CHECK(strstr(text, "\"tid\":1,\"args\":{\"name\":\"main\"}") != NULL);
    CHECK(strstr(text, "\"tid\":2,\"args\":{\"name\":\"worker \\\"1\\\"\"}") != NULL);
    CHECK(strstr(text, "\"args\":{\"file\":\"dir/\\\"odd\\\"\\u0009name\"}") != NULL);
    CHECK(strstr(text, "\"dur\":1.500,") != NULL);         // nanoseconds as microseconds, three decimals
    CHECK(strstr(text, "\"args\":{\"x\":4999,\"pass\":-4999}") != NULL);
    CHECK(strstr(text, "\"name\":\"backwards\",\"cat\":\"io\",\"ph\":\"X\",\"ts\":") != NULL);
    const char *back = text ? strstr(text, "\"name\":\"backwards\"") : NULL;
    CHECK(back && strstr(back, "\"dur\":0.000,") != NULL);
    free(text);
    trace_free(t);
}

enum { THREADS = 4, EVENTS_EACH = 20000 };

static void *fill_lane(void *arg) {
    trace_lane *lane = arg;
    trace_set_current(lane);
    for (int i = 0; i < EVENTS_EACH; i++) {
        int64_t now = trace_clock();
        trace_add(trace_current(), &(trace_event){"tile", "render", now, now, 1, {{"i", i, NULL}}});
    }
    return NULL;
}

// Threads append to their own lanes at once, with no lock: nothing is lost or mixed up.
static void test_threads(void) {
    trace *t = trace_new();
    CHECK(t != NULL);
    if (!t) return;
    pthread_t threads[THREADS];
    for (int i = 0; i < THREADS; i++) {
        char name[16];
        snprintf(name, sizeof name, "worker %d", i);
        CHECK(pthread_create(&threads[i], NULL, fill_lane, trace_lane_open(t, name)) == 0);
    }
    for (int i = 0; i < THREADS; i++) pthread_join(threads[i], NULL);
    CHECK(trace_event_count(t) == (size_t)THREADS * EVENTS_EACH);
    char *text = trace_text(t);
    for (int tid = 1; tid <= THREADS; tid++) {
        char last[64];
        snprintf(last, sizeof last, "\"tid\":%d,\"args\":{\"i\":%d}", tid, EVENTS_EACH - 1);
        CHECK(count_of(text, last) == 1);
    }
    free(text);
    CHECK(trace_current() == NULL); // this thread recorded nothing
    trace_free(t);
}

// Freeing a trace detaches the calling thread from it: nothing records into freed memory later.
static void test_free_detaches(void) {
    trace *t = trace_new();
    trace_lane *lane = t ? trace_lane_open(t, "main") : NULL;
    CHECK(lane != NULL);
    trace_set_current(lane);
    CHECK(trace_current() == lane);
    trace_free(t);
    CHECK(trace_current() == NULL);
}

static char *read_all(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *buf = malloc(1 << 22);
    size_t n = buf ? fread(buf, 1, (1 << 22) - 1, f) : 0;
    fclose(f);
    if (buf) buf[n] = '\0';
    return buf;
}

// A render on 1 and 3 threads with a trace attached: every tile pass is one "tile" event on some worker's row;
// the pixels are those of a render without a trace.
// tests/data/tiny-path.json at 40 pixels wide (3 x 1 tiles) and 40 spp (passes of 16, 16, 8 samples where no one
// watches and there is no time limit: TILES_FIRST_PASS); NULL (a failed check) when it cannot be read.
static glint_scene *tiny_path_40(void) {
    glint_scene *scene = NULL;
    glint_error err;
    CHECK(glint_scene_load(GLINT_SOURCE_DIR "/tests/data/tiny-path.json", &scene, &err) == GLINT_OK);
    if (!scene) return NULL;
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = 40;
    o.spp = 40;
    CHECK(glint_scene_override(scene, &o, &err) == GLINT_OK);
    return scene;
}

// Whether two images have the same size and the same pixels, bit for bit.
static bool same_pixels(const glint_image *a, const glint_image *b) {
    int w, h, bw, bh;
    const float *rgb, *brgb;
    glint_image_info(a, &w, &h, &rgb);
    glint_image_info(b, &bw, &bh, &brgb);
    return w == bw && h == bh && memcmp(rgb, brgb, (size_t)w * (size_t)h * 3 * sizeof *rgb) == 0;
}

static void test_traced_render(void) {
    glint_error err;
    glint_scene *scene = tiny_path_40();
    if (!scene) return;
    glint_image *plain = NULL;
    glint_render_options opt = {.threads = 2};
    CHECK(glint_render(scene, &opt, NULL, NULL, &plain, NULL, &err) == GLINT_OK);
    for (int threads = 1; threads <= 3; threads += 2) {
        glint_trace *t = glint_trace_new();
        CHECK(t && glint_trace_attach(t, "main", &err) == GLINT_OK);
        CHECK(glint_trace_attach(t, "again", &err) == GLINT_OK); // keeps its row
        glint_image *img = NULL;
        opt.threads = threads;
        CHECK(glint_render(scene, &opt, NULL, NULL, &img, NULL, &err) == GLINT_OK);
        CHECK(same_pixels(img, plain));
        const char *file = tmp_path("t.json");
        CHECK(glint_trace_write(t, file, &err) == GLINT_OK);
        char *text = read_all(file);
        CHECK(count_of(text, "\"name\":\"tile\"") == 3 * 3);
        CHECK(count_of(text, "\"name\":\"pass\"") == 3);
        CHECK(count_of(text, "\"name\":\"BVH build\"") == 1);
        CHECK(count_of(text, "\"name\":\"render\"") == 1);
        CHECK(count_of(text, "\"name\":\"thread_name\"") == (size_t)threads + 1); // workers, sample passes
        CHECK(count_of(text, "{\"name\":\"again\"}") == 0);
        CHECK(count_of(text, "{\"name\":\"worker 2\"}") == (threads == 3 ? 1u : 0u));
        free(text);
        // A file that cannot be written is an error naming it, and leaves nothing behind.
        CHECK(glint_trace_write(t, tmp_path("missing/t.json"), &err) == GLINT_ERR_RENDER);
        CHECK(strstr(err.message, "missing/t.json: cannot write") != NULL);
        CHECK(glint_trace_attach(NULL, NULL, &err) == GLINT_OK); // detached: the next render records nothing
        glint_image *untraced = NULL;
        CHECK(glint_render(scene, &opt, NULL, NULL, &untraced, NULL, &err) == GLINT_OK);
        CHECK(glint_trace_write(t, file, &err) == GLINT_OK);
        text = read_all(file);
        CHECK(count_of(text, "\"name\":\"tile\"") == 3 * 3);
        free(text);
        glint_image_free(untraced);
        glint_image_free(img);
        glint_trace_free(t);
    }
    CHECK(glint_trace_check_path(tmp_path("missing/t.json"), &err) == GLINT_ERR_RENDER);
    CHECK(glint_trace_check_path(tmp_path("t.json"), &err) == GLINT_OK);
    glint_image_free(plain);
    glint_scene_free(scene);
}

static void ignore_image(const glint_image *image, int spp_done, double fraction_done, void *user) {
    (void)image, (void)spp_done, (void)fraction_done, (void)user;
}

// The passes of a render someone watches (a live image) or a time limit may stop start at one sample: 1, 1, 2, 4, 8,
// 16 and 8 samples at 40 spp, seven "pass" events where an unwatched render has three; the image the same bytes.
static void test_watched_passes(void) {
    glint_error err;
    glint_scene *scene = tiny_path_40();
    if (!scene) return;
    glint_render_options plain_opt = {.threads = 2};
    glint_image *plain = NULL;
    CHECK(glint_render(scene, &plain_opt, NULL, NULL, &plain, NULL, &err) == GLINT_OK);
    for (int watched = 0; watched < 2; watched++) {
        glint_trace *t = glint_trace_new();
        CHECK(t && glint_trace_attach(t, "main", &err) == GLINT_OK);
        glint_render_options opt = {.threads = 2};
        if (watched) opt.live_image = ignore_image;
        else opt.time_limit = 1e6; // never reached: the passes are still cut from one sample
        glint_image *img = NULL;
        CHECK(glint_render(scene, &opt, NULL, NULL, &img, NULL, &err) == GLINT_OK);
        const char *file = tmp_path("watched.json");
        CHECK(glint_trace_write(t, file, &err) == GLINT_OK);
        char *text = read_all(file);
        CHECK(text && count_of(text, "\"name\":\"pass\"") == 7);
        CHECK(text && count_of(text, "\"name\":\"tile\"") == 3 * 7);
        free(text);
        CHECK(same_pixels(img, plain));
        CHECK(glint_trace_attach(NULL, NULL, &err) == GLINT_OK);
        glint_image_free(img);
        glint_trace_free(t);
    }
    glint_image_free(plain);
    glint_scene_free(scene);
}

int main(void) {
    if (!tmpdir_make("glint-trace")) return 1;
    test_json_strings();
    test_lane_growth_and_file();
    test_threads();
    test_free_detaches();
    test_traced_render();
    test_watched_passes();
    tmpdir_remove();
    return check_summary();
}
