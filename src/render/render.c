// render.c — the render stage: progressive sample passes over tiles handed out through an atomic counter to
// N threads, each pixel's samples drawn from generators seeded by (seed, pixel, sample) alone, so any thread
// count gives the same bytes, and a stop request leaves every pixel at the mean of its completed samples.
#include "accel/accel.h"
#include "core/clock.h"
#include "integrator/integrator.h"
#include "render/camera_batch.h"
#include "render/film.h"

#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum {
    TILE_SIZE = 16,
    MAX_THREADS = 256,
    MAX_PASSES = 33,            // 0, 1, 2, 4, ..., 2^30, spp: enough for any int spp
    PROGRESS_INTERVAL_MS = 200, // progress callbacks at most five times a second
};

// Set by glint_request_stop (possibly from a signal handler), polled before every sample, cleared when a
// render returns: a request made while no render runs stops the next one at once.
static _Alignas(64) atomic_int stop_requested; // read before every sample: a line of its own

void glint_request_stop(void) { atomic_store(&stop_requested, 1); }

static bool stop_is_requested(void) { return atomic_load_explicit(&stop_requested, memory_order_relaxed) != 0; }

// Work is a sequence of items, item = pass * tile_count + tile. Pass p renders samples
// [pass_start[p], pass_start[p+1]) of every pixel of the tile, adding them to the running sums in sample
// order, so the final mean is bit for bit the plain sum over samples 0..spp-1 divided by spp.
typedef struct render_job {
    const glint_scene *scene;
    glint_image *image;
    double *sums;                  ///< per-pixel running RGB sums between passes; NULL with a single pass
    int tiles_x, tile_count, pass_count;
    int pass_start[MAX_PASSES + 1];
    uint64_t total_samples;        ///< width * height * spp
    uint64_t stream;               ///< rng_seed_stream(seed), shared by every sample's generator
    atomic_int next_item;
    atomic_int *tile_passes;       ///< passes completed by each tile; pass p of a tile waits for p
    atomic_int waiters;            ///< workers blocked in wait_for_tile
    atomic_int stopping;           ///< a worker saw the stop request; waiters must give up
    pthread_mutex_t lock;
    pthread_cond_t tile_finished;
} render_job;

// One worker's state, on cache lines of its own: the counters that worker writes never share a line.
typedef struct worker {
    thread_stats stats;                           ///< the worker's counters, copied here when it ends
    _Alignas(64) _Atomic uint64_t samples_done;   ///< read by the progress thread while the worker runs
    render_job *job;
    pthread_t thread;
} worker;

// The progress reporter: a helper thread that wakes a few times a second and sums the workers' counters,
// so reports are time-based whatever the size of a tile or pass.
typedef struct progress_state {
    render_job *job;
    worker *workers;
    int worker_count;
    glint_progress_fn fn;
    void *user;
    bool finished;
    pthread_mutex_t lock;
    pthread_cond_t wake;
} progress_state;

// Pass boundaries 0, 1, 2, 4, 8, ..., spp: a stopped render has at least doubled its samples since the last
// complete pass, and a full render pays for log2(spp) visits of each pixel, a negligible cost.
static int plan_passes(int spp, int start[MAX_PASSES + 1]) {
    int n = 0;
    start[0] = 0;
    long next = 1;
    while (start[n] < spp) {
        start[n + 1] = next < spp ? (int)next : spp;
        n++;
        next *= 2;
    }
    return n;
}

// Stores a pixel's state after its samples [0, k) (k1: the end of this pass): its running sum for the next
// pass, and the mean of its samples so far in the image.
static void store_pixel(const render_job *job, size_t pixel, const double sum[3], int k, int k1) {
    if (job->sums && k1 < job->scene->settings.spp) memcpy(&job->sums[pixel * 3u], sum, 3 * sizeof *sum);
    if (k > 0) {
        float *px = &job->image->rgb[pixel * 3u];
        double inv = 1.0 / k; // one division for the three channels, at every pass of every pixel
        for (int c = 0; c < 3; c++) px[c] = (float)(sum[c] * inv);
    }
}

// Renders samples [k0, k1) of pixel (x, y), adding to the sums of earlier passes, and stores the mean of the
// samples completed so far; false when a stop request cut it short.
static bool render_pixel(const render_job *job, int x, int y, int k0, int k1, thread_stats *ts,
                         _Atomic uint64_t *progress) {
    const glint_scene *s = job->scene;
    const render_settings *rs = &s->settings;
    size_t pixel = (size_t)y * (size_t)rs->width + (size_t)x;
    double sum[3] = {0, 0, 0};
    if (k0 > 0) memcpy(sum, &job->sums[pixel * 3u], sizeof sum);
    int k = k0;
    bool stopped = false;
    // rng_for_sample(seed, pixel, k), its per-render and per-pixel parts computed once.
    uint64_t key = rng_pixel_key(rs->seed, (uint64_t)pixel);
    for (; k < k1; k++) {
        if (stop_is_requested()) { stopped = true; break; }
        rng r = rng_for_key(job->stream, key, (uint64_t)k);
        vec3 c = integrator_sample(s, x, y, (uint32_t)k, &r, ts);
        ts->samples++;
        atomic_store_explicit(progress, ts->samples, memory_order_relaxed);
        // A NaN or infinite sample would poison the pixel: drop it (it counts as black), count it, report it.
        if (!v3_is_finite(c)) { ts->discarded_samples++; continue; }
        sum[0] += c.x;
        sum[1] += c.y;
        sum[2] += c.z;
    }
    store_pixel(job, pixel, sum, k, k1);
    return !stopped;
}

// One pass of one tile in the path tracer: render_pixel over the tile's pixels, except that the samples' camera
// rays (and generators) are made CAMERA_BATCH at a time, in vector instructions (camera_batch.h), before their
// paths are traced. Same samples, same order, same sums: the same bytes.
static bool render_tile_path(const render_job *job, int x0, int y0, int x1, int y1, int k0, int k1, thread_stats *ts,
                             _Atomic uint64_t *progress) {
    const glint_scene *s = job->scene;
    const render_settings *rs = &s->settings;
    int w = x1 - x0, spp = k1 - k0, items = w * (y1 - y0) * spp; // item j: sample k0 + j % spp of pixel j / spp
    // The batch cursor (gx, gy, gk) runs ahead of the tracing cursor (x, y, k) by up to CAMERA_BATCH items.
    int gx = x0, gy = y0, gk = k0;
    uint64_t gkey = rng_pixel_key(rs->seed, (uint64_t)gy * (uint64_t)rs->width + (uint64_t)gx);
    int x = x0, y = y0, k = k0;
    size_t pixel = (size_t)y * (size_t)rs->width + (size_t)x;
    double sum[3] = {0, 0, 0};
    if (k0 > 0) memcpy(sum, &job->sums[pixel * 3u], sizeof sum);
    camera_batch cb;
    for (int j = 0; j < items; j += CAMERA_BATCH) {
        int n = items - j < CAMERA_BATCH ? items - j : CAMERA_BATCH;
        for (int i = 0; i < CAMERA_BATCH; i++) {
            if (i >= n) { // lanes past the tile's end repeat the first
                cb.x[i] = cb.x[0], cb.y[i] = cb.y[0], cb.key[i] = cb.key[0], cb.sample[i] = cb.sample[0];
                continue;
            }
            cb.x[i] = gx, cb.y[i] = gy, cb.key[i] = gkey, cb.sample[i] = (uint64_t)gk;
            if (++gk == k1) {
                gk = k0;
                if (++gx == x1) { gx = x0; gy++; }
                if (gy < y1) gkey = rng_pixel_key(rs->seed, (uint64_t)gy * (uint64_t)rs->width + (uint64_t)gx);
            }
        }
        camera_batch_make(s, job->stream, &cb);
        for (int i = 0; i < n; i++) {
            if (stop_is_requested()) {
                store_pixel(job, pixel, sum, k, k1);
                return false;
            }
            rng r = cb.r[i];
            vec3 c = path_trace(s, cb.o[i], cb.d[i], &r, ts);
            ts->samples++;
            atomic_store_explicit(progress, ts->samples, memory_order_relaxed);
            // A NaN or infinite sample would poison the pixel: drop it (it counts as black), count it, report it.
            if (!v3_is_finite(c)) ts->discarded_samples++;
            else {
                sum[0] += c.x;
                sum[1] += c.y;
                sum[2] += c.z;
            }
            if (++k < k1) continue;
            store_pixel(job, pixel, sum, k1, k1); // this pixel's samples of the pass are done
            k = k0;
            if (++x == x1) { x = x0; y++; }
            if (y == y1) return true;
            pixel = (size_t)y * (size_t)rs->width + (size_t)x;
            sum[0] = sum[1] = sum[2] = 0.0;
            if (k0 > 0) memcpy(sum, &job->sums[pixel * 3u], sizeof sum);
        }
    }
    return true;
}

// Renders one pass of one tile; false when stopped part-way (pixels not reached keep the previous pass's mean).
static bool render_tile(const render_job *job, int tile, int pass, thread_stats *ts, _Atomic uint64_t *progress) {
    const render_settings *rs = &job->scene->settings;
    int x0 = (tile % job->tiles_x) * TILE_SIZE, y0 = (tile / job->tiles_x) * TILE_SIZE;
    int x1 = x0 + TILE_SIZE < rs->width ? x0 + TILE_SIZE : rs->width;
    int y1 = y0 + TILE_SIZE < rs->height ? y0 + TILE_SIZE : rs->height;
    int k0 = job->pass_start[pass], k1 = job->pass_start[pass + 1];
    if (rs->integrator == INTEGRATOR_PATH) return render_tile_path(job, x0, y0, x1, y1, k0, k1, ts, progress);
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++)
            if (!render_pixel(job, x, y, k0, k1, ts, progress)) return false;
    return true;
}

// Wakes the workers waiting for a tile; the waiters count (sequentially consistent, as is the tile store
// before it) spares the mutex when, as nearly always, nobody waits.
static void wake_waiters(render_job *job) {
    if (atomic_load(&job->waiters) == 0) return;
    pthread_mutex_lock(&job->lock);
    pthread_cond_broadcast(&job->tile_finished);
    pthread_mutex_unlock(&job->lock);
}

// Blocks until the tile has finished `pass` passes; false when the render is stopping instead. Only waits
// when fewer tiles than threads remain between a tile's consecutive passes.
static bool wait_for_tile(render_job *job, int tile, int pass) {
    if (atomic_load(&job->tile_passes[tile]) >= pass) return true;
    pthread_mutex_lock(&job->lock);
    atomic_fetch_add(&job->waiters, 1);
    while (atomic_load(&job->tile_passes[tile]) < pass && !atomic_load(&job->stopping))
        pthread_cond_wait(&job->tile_finished, &job->lock);
    atomic_fetch_sub(&job->waiters, 1);
    pthread_mutex_unlock(&job->lock);
    return atomic_load(&job->tile_passes[tile]) >= pass;
}

static void *worker_main(void *arg) {
    worker *w = arg;
    render_job *job = w->job;
    thread_stats local = {0}; // on this thread's stack: the hot counters are never shared
    int items = job->pass_count * job->tile_count;
    for (;;) {
        if (stop_is_requested()) break;
        int item = atomic_fetch_add(&job->next_item, 1);
        if (item >= items) break;
        int pass = item / job->tile_count, tile = item % job->tile_count;
        if (!wait_for_tile(job, tile, pass)) break;
        if (!render_tile(job, tile, pass, &local, &w->samples_done)) break;
        atomic_store(&job->tile_passes[tile], pass + 1);
        wake_waiters(job);
    }
    // Whoever leaves early releases the waiters: the tiles they wait for may never finish now.
    if (stop_is_requested()) {
        pthread_mutex_lock(&job->lock);
        atomic_store(&job->stopping, 1);
        pthread_cond_broadcast(&job->tile_finished);
        pthread_mutex_unlock(&job->lock);
    }
    w->stats = local;
    return NULL;
}

static uint64_t samples_so_far(const progress_state *p) {
    uint64_t n = 0;
    for (int i = 0; i < p->worker_count; i++)
        n += atomic_load_explicit(&p->workers[i].samples_done, memory_order_relaxed);
    return n;
}

static void *progress_main(void *arg) {
    progress_state *p = arg;
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    pthread_mutex_lock(&p->lock);
    while (!p->finished) {
        next.tv_nsec += PROGRESS_INTERVAL_MS * 1000000L;
        if (next.tv_nsec >= 1000000000L) { next.tv_sec++; next.tv_nsec -= 1000000000L; }
        int rc = 0;
        while (!p->finished && rc != ETIMEDOUT) rc = pthread_cond_timedwait(&p->wake, &p->lock, &next);
        if (p->finished) break;
        // Call out without the lock: a slow terminal must not hold up the end of the render.
        pthread_mutex_unlock(&p->lock);
        p->fn((double)samples_so_far(p) / (double)p->job->total_samples, p->user);
        pthread_mutex_lock(&p->lock);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

// Starts the progress thread; false (and no progress reports but the last) when it cannot be started.
static bool progress_start(progress_state *p, pthread_t *thread) {
    pthread_condattr_t attr;
    if (pthread_condattr_init(&attr) != 0) return false;
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    int rc = pthread_cond_init(&p->wake, &attr);
    pthread_condattr_destroy(&attr);
    if (rc != 0) return false;
    pthread_mutex_init(&p->lock, NULL);
    if (pthread_create(thread, NULL, progress_main, p) == 0) return true;
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
    return false;
}

static void progress_stop(progress_state *p, pthread_t thread) {
    pthread_mutex_lock(&p->lock);
    p->finished = true;
    pthread_cond_signal(&p->wake);
    pthread_mutex_unlock(&p->lock);
    pthread_join(thread, NULL);
    pthread_cond_destroy(&p->wake);
    pthread_mutex_destroy(&p->lock);
}

static int online_cpus(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

// Sets up the job's passes, tiles and buffers; false when out of memory.
static bool job_init(render_job *job, const glint_scene *s, glint_image *img) {
    const render_settings *rs = &s->settings;
    memset(job, 0, sizeof *job);
    job->scene = s;
    job->image = img;
    job->tiles_x = (rs->width + TILE_SIZE - 1) / TILE_SIZE;
    job->tile_count = job->tiles_x * ((rs->height + TILE_SIZE - 1) / TILE_SIZE);
    job->pass_count = plan_passes(rs->spp, job->pass_start);
    job->total_samples = (uint64_t)rs->width * (uint64_t)rs->height * (uint64_t)rs->spp;
    job->stream = rng_seed_stream(rs->seed);
    atomic_init(&job->next_item, 0);
    atomic_init(&job->waiters, 0);
    atomic_init(&job->stopping, 0);
    if (job->pass_count > 1) {
        job->sums = malloc((size_t)rs->width * (size_t)rs->height * 3u * sizeof *job->sums);
        if (!job->sums) return false;
    }
    job->tile_passes = malloc((size_t)job->tile_count * sizeof *job->tile_passes);
    if (!job->tile_passes) { free(job->sums); return false; }
    for (int i = 0; i < job->tile_count; i++) atomic_init(&job->tile_passes[i], 0);
    pthread_mutex_init(&job->lock, NULL);
    pthread_cond_init(&job->tile_finished, NULL);
    return true;
}

static void job_free(render_job *job) {
    pthread_cond_destroy(&job->tile_finished);
    pthread_mutex_destroy(&job->lock);
    free(job->tile_passes);
    free(job->sums);
}

glint_status glint_render(glint_scene *s, const glint_render_options *opt, glint_progress_fn progress, void *user,
                          glint_image **out, glint_render_stats *stats, glint_error *err) {
    *out = NULL;
    double t0 = clock_seconds();
    glint_status st = scene_prepare(s, err);
    if (st != GLINT_OK) return st;
    double t_built = clock_seconds();
    const render_settings *rs = &s->settings;
    int threads = opt && opt->threads > 0 ? opt->threads : online_cpus();
    if (threads > MAX_THREADS) threads = MAX_THREADS;

    glint_image *img = film_new(rs->width, rs->height, rs->transform);
    render_job job;
    bool job_ready = img && job_init(&job, s, img);
    worker *workers = job_ready ? aligned_alloc(64, sizeof(worker) * (size_t)threads) : NULL;
    if (!workers) {
        if (job_ready) job_free(&job);
        glint_image_free(img);
        snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image on %d threads", rs->width,
                 rs->height, threads);
        return GLINT_ERR_RENDER;
    }
    memset(workers, 0, sizeof(worker) * (size_t)threads);
    for (int i = 0; i < threads; i++) {
        workers[i].job = &job;
        atomic_init(&workers[i].samples_done, 0);
    }

    progress_state prog = {.job = &job, .workers = workers, .worker_count = threads, .fn = progress, .user = user};
    pthread_t prog_thread;
    bool prog_running = progress && progress_start(&prog, &prog_thread);

    int started = 0; // worker threads 1..started run; the calling thread is worker 0
    for (int i = 1; i < threads; i++) {
        if (pthread_create(&workers[i].thread, NULL, worker_main, &workers[i]) != 0) break;
        started = i;
    }
    worker_main(&workers[0]);
    for (int i = 1; i <= started; i++) pthread_join(workers[i].thread, NULL);
    if (prog_running) progress_stop(&prog, prog_thread);

    thread_stats total = {0};
    for (int i = 0; i <= started; i++) {
        total.rays += workers[i].stats.rays;
        total.shadow_rays += workers[i].stats.shadow_rays;
        total.discarded_samples += workers[i].stats.discarded_samples;
        total.samples += workers[i].stats.samples;
    }
    if (progress) progress((double)total.samples / (double)job.total_samples, user);
    if (stats) {
        memset(stats, 0, sizeof *stats);
        stats->rays = total.rays;
        stats->shadow_rays = total.shadow_rays;
        stats->discarded_samples = total.discarded_samples;
        stats->samples = total.samples;
        accel_stats as;
        accel_get_stats(s->accel, &as);
        stats->bvh_nodes = as.nodes;
        stats->bvh_leaves = as.leaves;
        stats->bvh_depth = as.depth;
        stats->build_seconds = as.build_seconds > 0 ? as.build_seconds : t_built - t0;
        double t_end = clock_seconds();
        stats->wall_seconds = t_end - t0;
        stats->render_seconds = t_end - t_built;
        stats->threads = started + 1;
    }
    free(workers);
    job_free(&job);
    atomic_store(&stop_requested, 0); // this render has answered any stop request made so far
    *out = img;
    if (total.samples < job.total_samples) {
        snprintf(err->message, sizeof err->message, "interrupted after %llu of %llu samples",
                 (unsigned long long)total.samples, (unsigned long long)job.total_samples);
        return GLINT_ERR_INTERRUPTED;
    }
    return GLINT_OK;
}
