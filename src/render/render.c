// render.c — the render stage: tiles handed out through an atomic counter to N threads, each pixel's
// samples drawn from generators seeded by (seed, pixel, sample) alone, so any thread count gives the
// same bytes.
#include "accel/accel.h"
#include "integrator/integrator.h"
#include "render/film.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { TILE_SIZE = 16, MAX_THREADS = 256 };

static atomic_int stop_requested;

void glint_request_stop(void) { atomic_store(&stop_requested, 1); }

typedef struct render_job {
    const glint_scene *scene;
    glint_image *image;
    int tiles_x, tile_count;
    atomic_int next_tile;
    atomic_int tiles_done;
    atomic_int interrupted;
    pthread_mutex_t progress_lock;
    glint_progress_fn progress;
    void *user;
    double last_report;
} render_job;

typedef struct worker {
    thread_stats stats;
    render_job *job;
    pthread_t thread;
} worker;

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// Renders every sample of one pixel and stores its mean; false when a stop was requested mid-pixel.
static void render_pixel(const glint_scene *s, glint_image *img, int x, int y, thread_stats *ts) {
    const render_settings *rs = &s->settings;
    uint64_t pixel = (uint64_t)y * (uint64_t)rs->width + (uint64_t)x;
    double sum[3] = {0, 0, 0};
    for (int k = 0; k < rs->spp; k++) {
        rng r = rng_for_sample(rs->seed, pixel, (uint64_t)k);
        vec3 c = integrator_sample(s, x, y, (uint32_t)k, &r, ts);
        ts->samples++;
        // A NaN or infinite sample would poison the pixel: drop it, count it, report it.
        if (!v3_is_finite(c)) { ts->discarded_samples++; continue; }
        sum[0] += c.x;
        sum[1] += c.y;
        sum[2] += c.z;
    }
    float *px = &img->rgb[pixel * 3u];
    for (int c = 0; c < 3; c++) px[c] = (float)(sum[c] / rs->spp);
}

static void report_progress(render_job *job) {
    if (!job->progress) return;
    if (pthread_mutex_trylock(&job->progress_lock) != 0) return;
    double t = now_seconds();
    int done = atomic_load(&job->tiles_done);
    if (t - job->last_report >= 0.2 || done == job->tile_count) {
        job->last_report = t;
        job->progress((double)done / job->tile_count, job->user);
    }
    pthread_mutex_unlock(&job->progress_lock);
}

static void *worker_main(void *arg) {
    worker *w = arg;
    render_job *job = w->job;
    const glint_scene *s = job->scene;
    thread_stats local = {0};
    for (;;) {
        if (atomic_load_explicit(&stop_requested, memory_order_relaxed)) {
            atomic_store(&job->interrupted, 1);
            break;
        }
        int tile = atomic_fetch_add(&job->next_tile, 1);
        if (tile >= job->tile_count) break;
        int x0 = (tile % job->tiles_x) * TILE_SIZE, y0 = (tile / job->tiles_x) * TILE_SIZE;
        int x1 = x0 + TILE_SIZE < s->settings.width ? x0 + TILE_SIZE : s->settings.width;
        int y1 = y0 + TILE_SIZE < s->settings.height ? y0 + TILE_SIZE : s->settings.height;
        for (int y = y0; y < y1; y++)
            for (int x = x0; x < x1; x++) render_pixel(s, job->image, x, y, &local);
        atomic_fetch_add(&job->tiles_done, 1);
        report_progress(job);
    }
    w->stats = local;
    return NULL;
}

static int online_cpus(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

glint_status glint_render(glint_scene *s, const glint_render_options *opt, glint_progress_fn progress, void *user,
                          glint_image **out, glint_render_stats *stats, glint_error *err) {
    *out = NULL;
    double t0 = now_seconds();
    glint_status st = scene_prepare(s, err);
    if (st != GLINT_OK) return st;
    double t_built = now_seconds();
    const render_settings *rs = &s->settings;
    glint_image *img = film_new(rs->width, rs->height, rs->transform);
    if (!img) {
        snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image", rs->width, rs->height);
        return GLINT_ERR_RENDER;
    }
    int threads = opt && opt->threads > 0 ? opt->threads : online_cpus();
    if (threads > MAX_THREADS) threads = MAX_THREADS;

    render_job job;
    memset(&job, 0, sizeof job);
    job.scene = s;
    job.image = img;
    job.tiles_x = (rs->width + TILE_SIZE - 1) / TILE_SIZE;
    job.tile_count = job.tiles_x * ((rs->height + TILE_SIZE - 1) / TILE_SIZE);
    atomic_init(&job.next_tile, 0);
    atomic_init(&job.tiles_done, 0);
    atomic_init(&job.interrupted, 0);
    pthread_mutex_init(&job.progress_lock, NULL);
    job.progress = progress;
    job.user = user;
    job.last_report = t_built;

    worker *workers = aligned_alloc(64, sizeof(worker) * (size_t)threads);
    if (!workers) {
        glint_image_free(img);
        snprintf(err->message, sizeof err->message, "out of memory for %d threads", threads);
        return GLINT_ERR_RENDER;
    }
    memset(workers, 0, sizeof(worker) * (size_t)threads);
    int started = 0;
    for (int i = 0; i < threads; i++) {
        workers[i].job = &job;
        if (i == 0) continue; // the calling thread is worker 0
        if (pthread_create(&workers[i].thread, NULL, worker_main, &workers[i]) != 0) break;
        started = i;
    }
    worker_main(&workers[0]);
    for (int i = 1; i <= started; i++) pthread_join(workers[i].thread, NULL);
    pthread_mutex_destroy(&job.progress_lock);

    if (stats) {
        memset(stats, 0, sizeof *stats);
        for (int i = 0; i <= started; i++) {
            stats->rays += workers[i].stats.rays;
            stats->shadow_rays += workers[i].stats.shadow_rays;
            stats->discarded_samples += workers[i].stats.discarded_samples;
            stats->samples += workers[i].stats.samples;
        }
        accel_stats as;
        accel_get_stats(s->accel, &as);
        stats->bvh_nodes = as.nodes;
        stats->bvh_leaves = as.leaves;
        stats->bvh_depth = as.depth;
        stats->build_seconds = t_built - t0;
        stats->wall_seconds = now_seconds() - t0;
        stats->threads = started + 1;
    }
    free(workers);
    *out = img;
    if (atomic_load(&job.interrupted)) {
        snprintf(err->message, sizeof err->message, "interrupted");
        return GLINT_ERR_INTERRUPTED;
    }
    return GLINT_OK;
}
