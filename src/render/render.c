// render.c — the render stage: progressive sample passes over tiles handed out through an atomic counter to
// N threads, each pixel's samples drawn from generators seeded by (seed, pixel, sample) alone, so any thread
// count gives the same bytes, and a stop request leaves every pixel at the mean of its completed samples.
#include "render/render.h"
#include "core/clock.h"
#include "core/thread_pool.h"
#include "core/trace.h"
#include "film/film.h"
#include "io/image_write.h"
#include "render/checkpoint.h"
#include "render/frame.h"
#include "render/tiles.h"

#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum {
    MAX_THREADS = 256,
    MAX_PASSES = TILES_MAX_PASSES,
    PROGRESS_INTERVAL_MS = 200, // progress callbacks at most five times a second
    PASS_RUN = 1,
    PASS_SKIP = 2,
};

// Work is a sequence of items, item = pass * tile_count + tile. Pass p renders samples
// [pass_start[p], pass_start[p+1]) of every pixel of the tile, adding them to the running sums in sample
// order, so the final mean is bit for bit the plain sum over samples 0..spp-1 divided by spp.
typedef struct render_job {
    const glint_scene *scene;
    const integrator *integrator;
    film film;
    int region[4];                 ///< the pixels rendered, X0, Y0, X1, Y1 in full-image coordinates
    tiles grid;                    ///< the region's tiles and the sample passes (render/tiles.h, shared with glint-mpi)
    uint64_t total_samples;        ///< the region's pixels * spp
    atomic_int next_item;
    atomic_int *tile_passes;       ///< passes completed by each tile; pass p of a tile waits for p
    atomic_int waiters;            ///< workers blocked in wait_for_tile
    atomic_int stopping;           ///< a worker saw the stop request; waiters must give up
    // What stops this render, and no other: the caller's cancel token (polled before every sample when given)
    // and the render's own flag (a failed checkpoint; polled before every sample when there is no token, else
    // between tiles).
    const atomic_int *cancel;
    _Alignas(64) atomic_int stop;  ///< read before every sample: a line of its own
    double deadline;               ///< clock_seconds() after which no new pass starts (0: no time limit)
    bool gated;                    ///< a time limit or checkpoints: each pass waits for its first tile's decision
    atomic_int pass_decision[MAX_PASSES]; ///< when gated: 0 undecided, PASS_RUN or PASS_SKIP
    // Checkpoints, resumes and adaptive sampling only: each pixel's count of samples, so that any state can be
    // saved and continued, and a pixel can stop before the others.
    uint32_t *counts;              ///< samples each pixel of the region has completed; NULL otherwise
    float noise_threshold;         ///< adaptive sampling (film_pixel_converged); 0: off
    uint64_t resumed_samples;      ///< samples the resumed checkpoint brought (sum of counts at the start)
    const char *checkpoint;        ///< the file written after each pass and at the end, or NULL
    checkpoint_identity identity;  ///< of this render, as checkpoints record it
    atomic_int tiles_done[MAX_PASSES]; ///< with checkpoints: tiles that have finished each pass
    atomic_int failed;             ///< a checkpoint could not be written: the render stops, with `failure`
    glint_error failure;
    // Traced renders only: when each pass's first tile began and its last one ended (trace_clock; 0: not yet).
    _Atomic int64_t pass_began[MAX_PASSES], pass_ended[MAX_PASSES];
    pthread_mutex_t lock;
    pthread_cond_t tile_finished;
} render_job;

// One worker's state, on cache lines of its own: the counters that worker writes never share a line.
typedef struct worker {
    thread_stats stats;                           ///< the worker's counters, copied here when it ends
    _Alignas(64) _Atomic uint64_t samples_done;   ///< read by the progress thread while the worker runs
    render_job *job;
    trace_lane *lane;                             ///< the worker's row of the trace; NULL: not traced
} worker;

// The progress reporter: a helper thread that wakes a few times a second and sums the workers' counters,
// so reports are time-based whatever the size of a tile or pass.
typedef struct progress_state {
    render_job *job;
    worker *workers;
    int worker_count;
    render_progress_fn fn;          ///< may be NULL
    void *user;
    render_live_fn live_image; ///< may be NULL
    void *live_user;
    bool finished;
    pthread_mutex_t lock;
    pthread_cond_t wake;
} progress_state;

// Samples [k0, k1) of the pixels [x0, x1) x [y0, y1) (rect, full-image coordinates) into the film; false when
// stopped part-way (ft then says where: pixels not reached keep the previous pass's mean).
// Whether the render must stop: its caller's token or its own flag is set.
static bool job_stopping(const render_job *job) {
    return atomic_load_explicit(&job->stop, memory_order_relaxed) != 0 ||
           (job->cancel && atomic_load_explicit(job->cancel, memory_order_relaxed) != 0);
}

static bool render_rect(render_job *job, const int rect[4], int k0, int k1, thread_stats *ts,
                        _Atomic uint64_t *progress, film_tile *ft) {
    tile_pass tp = {.x0 = rect[0], .y0 = rect[1], .x1 = rect[2], .y1 = rect[3], .k0 = k0, .k1 = k1,
                    .stop = job->cancel ? job->cancel : &job->stop};
    film_tile_begin(ft, &job->film, tp.x0, tp.y0, tp.x1, tp.y1, k0, k1, ts, progress);
    return job->integrator->render_tile(job->integrator, &tp, ft, ts);
}

// Whether pixel i (film index) still takes samples before the count k1: it has fewer, and adaptive sampling has not
// stopped it (its count is a pass boundary where its estimated error was below the threshold).
static bool pixel_needs(const render_job *job, size_t i, uint32_t k1) {
    uint32_t c = job->counts[i];
    return c < k1 && !(job->noise_threshold > 0.0f && film_pixel_converged(&job->film, i, c, job->noise_threshold));
}

// Samples [k0, k1) of the pixels run[0] <= x < run[2] of row run[1] (or of the whole rect), then their counts: the
// pixels before a stop have k1, the one it came in has ft.k, the rest keep k0. False when stopped.
static bool render_counted_rect(render_job *job, const int r[4], uint32_t k0, uint32_t k1, thread_stats *ts,
                                _Atomic uint64_t *progress) {
    film_tile ft;
    film *f = &job->film;
    bool done = render_rect(job, r, (int)k0, (int)k1, ts, progress, &ft);
    for (int y = r[1]; y < r[3]; y++)
        for (int x = r[0]; x < r[2]; x++) {
            bool before = done || y < ft.y || (y == ft.y && x < ft.x);
            if (before || (x == ft.x && y == ft.y)) job->counts[film_pixel_index(f, x, y)] = before ? k1 : (uint32_t)ft.k;
        }
    return done;
}

// A tile pass when every pixel's count is kept (checkpoints, resumes, adaptive sampling). A pixel continues from
// the samples it has, whatever the pass says: a resumed tile may have been stopped part-way, or rendered to a
// smaller spp, and adaptive sampling stops pixels one by one. The sum after k samples does not depend on where the
// passes split them, so the image is an uninterrupted one's.
static bool render_tile_counted(render_job *job, const int r[4], int pass, thread_stats *ts,
                                _Atomic uint64_t *progress) {
    const uint32_t k1 = (uint32_t)job->grid.pass_start[pass + 1];
    film *f = &job->film;
    uint32_t *counts = job->counts, lo = UINT32_MAX, hi = 0;
    bool all = true, none = true;
    for (int y = r[1]; y < r[3]; y++)
        for (int x = r[0]; x < r[2]; x++) {
            size_t i = film_pixel_index(f, x, y);
            lo = counts[i] < lo ? counts[i] : lo;
            hi = counts[i] > hi ? counts[i] : hi;
            bool needs = pixel_needs(job, i, k1);
            all = all && needs;
            none = none && !needs;
        }
    if (none) return true; // a resumed tile that has these samples already, or every pixel stopped
    // The whole tile at one count: one tile pass from there, as an uninterrupted render makes it.
    if (all && lo == hi) return render_counted_rect(job, r, lo, k1, ts, progress);
    // Otherwise runs of a row's pixels that take samples from one count, each a tile pass of its own.
    for (int y = r[1]; y < r[3]; y++)
        for (int x = r[0]; x < r[2];) {
            size_t i = film_pixel_index(f, x, y);
            if (!pixel_needs(job, i, k1)) {
                x++;
                continue;
            }
            int x1 = x + 1;
            while (x1 < r[2] && counts[film_pixel_index(f, x1, y)] == counts[i] &&
                   pixel_needs(job, film_pixel_index(f, x1, y), k1))
                x1++;
            int run[4] = {x, y, x1, y + 1};
            if (!render_counted_rect(job, run, counts[i], k1, ts, progress)) return false;
            x = x1;
        }
    return true;
}

// Renders one pass of one tile; false when stopped part-way (pixels not reached keep the previous pass's mean).
// Tiles are the cells of the full image's 16x16 grid, clipped to the region: a region's pixels are rendered in
// the same tiles, batches and order as in a full render.
static bool render_tile(render_job *job, int tile, int pass, thread_stats *ts, _Atomic uint64_t *progress) {
    int rect[4];
    tiles_rect(&job->grid, tile, rect);
    if (job->counts) return render_tile_counted(job, rect, pass, ts, progress);
    film_tile ft;
    return render_rect(job, rect, job->grid.pass_start[pass], job->grid.pass_start[pass + 1], ts, progress, &ft);
}

// "wait" on the trace: a worker idle from `began` until now, for `what` (tile -1: the whole pass).
static void trace_wait(trace_lane *lane, int64_t began, const char *what, int tile, int pass) {
    trace_event e = {"wait", "render", began, trace_clock(), 2, {{"for", 0, what}, {"pass", pass, NULL}}};
    if (tile >= 0) e.args[e.arg_count++] = (trace_arg){"tile", tile, NULL};
    trace_add(lane, &e);
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
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    pthread_mutex_lock(&job->lock);
    atomic_fetch_add(&job->waiters, 1);
    bool waited = false;
    while (atomic_load(&job->tile_passes[tile]) < pass && !atomic_load(&job->stopping)) {
        waited = true;
        pthread_cond_wait(&job->tile_finished, &job->lock);
    }
    atomic_fetch_sub(&job->waiters, 1);
    pthread_mutex_unlock(&job->lock);
    if (lane && waited) trace_wait(lane, began, "the tile's previous pass", tile, pass);
    return atomic_load(&job->tile_passes[tile]) >= pass;
}

// Writes a checkpoint of the job as it is now (every worker waits or has left); false, with the render
// stopping and the message kept, when it cannot be written.
static bool job_write_checkpoint(render_job *job) {
    size_t pixels = (size_t)job->film.image->width * (size_t)job->film.image->height;
    uint32_t complete = UINT32_MAX;
    for (size_t i = 0; i < pixels; i++) complete = job->counts[i] < complete ? job->counts[i] : complete;
    checkpoint_plane planes[] = {{"count", CHECKPOINT_U32, 1, job->counts},
                                 {"rgb", CHECKPOINT_F64, 3, job->film.sums},
                                 {"rgb_odd", CHECKPOINT_F64, 3, job->film.odd_sums}};
    glint_error e;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    // The odd-numbered samples' sums with adaptive sampling alone: its decisions are made from them.
    size_t plane_count = job->film.odd_sums ? 3 : 2;
    glint_status st = checkpoint_write(job->checkpoint, &job->identity, job->film.spp, (int)complete, planes,
                                       plane_count, &e);
    if (lane)
        trace_add(lane, &(trace_event){"checkpoint write", "io", began, trace_clock(), 2,
                                       {{"file", 0, job->checkpoint}, {"spp", complete, NULL}}});
    if (st == GLINT_OK) return true;
    if (atomic_exchange(&job->failed, 1) == 0) job->failure = e;
    atomic_store(&job->stop, 1);
    return false;
}

// Blocks until every tile has finished `pass`; false when the render is stopping instead.
static bool wait_for_pass(render_job *job, int pass) {
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    pthread_mutex_lock(&job->lock);
    atomic_fetch_add(&job->waiters, 1);
    bool waited = false;
    while (atomic_load(&job->tiles_done[pass]) < job->grid.tile_count && !atomic_load(&job->stopping)) {
        waited = true;
        pthread_cond_wait(&job->tile_finished, &job->lock);
    }
    atomic_fetch_sub(&job->waiters, 1);
    pthread_mutex_unlock(&job->lock);
    if (lane && waited) trace_wait(lane, began, "the pass's end (checkpoint)", -1, pass);
    return atomic_load(&job->tiles_done[pass]) >= job->grid.tile_count;
}

// Whether pass `pass` runs, under a time limit or with checkpoints: the worker that takes its first tile decides
// once for everyone (items are handed out in order, so no tile of a pass is taken before its first); the others
// wait for that decision. With checkpoints it first waits for the previous pass to end everywhere and writes
// one; under a time limit it asks the clock. Every pixel thus ends with the same passes: the image of a shorter
// render, and a checkpoint of one.
static bool pass_may_run(render_job *job, int pass, int tile) {
    if (tile == 0) {
        if (job->checkpoint && (!wait_for_pass(job, pass - 1) || !job_write_checkpoint(job))) return false;
        int d = job->deadline > 0.0 && clock_seconds() > job->deadline ? PASS_SKIP : PASS_RUN;
        pthread_mutex_lock(&job->lock);
        atomic_store(&job->pass_decision[pass], d);
        pthread_cond_broadcast(&job->tile_finished);
        pthread_mutex_unlock(&job->lock);
        return d == PASS_RUN;
    }
    int d;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    pthread_mutex_lock(&job->lock);
    atomic_fetch_add(&job->waiters, 1);
    bool waited = false;
    while ((d = atomic_load(&job->pass_decision[pass])) == 0 && !atomic_load(&job->stopping) && !job_stopping(job)) {
        waited = true;
        // A stop request sets a flag and wakes nobody: look at it again every 50 ms.
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 50000000L;
        if (until.tv_nsec >= 1000000000L) { until.tv_sec++; until.tv_nsec -= 1000000000L; }
        pthread_cond_timedwait(&job->tile_finished, &job->lock, &until);
    }
    atomic_fetch_sub(&job->waiters, 1);
    pthread_mutex_unlock(&job->lock);
    if (lane && waited) trace_wait(lane, began, "the pass's start", -1, pass);
    return d == PASS_RUN;
}

// Keeps *a at most (below true) or at least (below false) v.
static void atomic_bound(_Atomic int64_t *a, int64_t v, bool below) {
    int64_t now = atomic_load_explicit(a, memory_order_relaxed);
    while ((now == 0 || (below ? v < now : v > now)) &&
           !atomic_compare_exchange_weak_explicit(a, &now, v, memory_order_relaxed, memory_order_relaxed)) {}
}

// "tile" on the worker's row of the trace, and the pass's extent so far.
static void trace_tile(render_job *job, trace_lane *lane, int tile, int pass, int64_t began, bool done) {
    int r[4];
    tiles_rect(&job->grid, tile, r);
    int64_t ended = trace_clock();
    trace_event e = {"tile", "render", began, ended, 6,
                     {{"x", r[0], NULL}, {"y", r[1], NULL}, {"w", r[2] - r[0], NULL}, {"h", r[3] - r[1], NULL},
                      {"pass", pass, NULL}, {"samples", tiles_pass_samples(&job->grid, pass), NULL}}};
    if (!done) e.args[e.arg_count++] = (trace_arg){"stopped", 1, NULL};
    trace_add(lane, &e);
    atomic_bound(&job->pass_began[pass], began, true);
    atomic_bound(&job->pass_ended[pass], ended, false);
}

// Worker `index` of the render: one item of the pool's job (core/thread_pool), whichever thread runs it.
static void worker_main(void *arg, size_t index) {
    worker *w = &((worker *)arg)[index];
    render_job *job = w->job;
    thread_stats local = {0}; // on this thread's stack: the hot counters are never shared
    int items = job->grid.pass_count * job->grid.tile_count;
    trace_lane *own = trace_current(); // the row of the thread that runs this worker, given back at the end
    trace_set_current(w->lane);        // for what records deeper down: checkpoints, waits
    for (;;) {
        if (job_stopping(job)) break;
        int item = atomic_fetch_add(&job->next_item, 1);
        if (item >= items) break;
        int pass = item / job->grid.tile_count, tile = item % job->grid.tile_count;
        if (job->gated && pass > 0 && !pass_may_run(job, pass, tile)) break;
        if (!wait_for_tile(job, tile, pass)) break;
        // Tracing off: one test of a pointer before and after each tile pass, nothing per sample.
        int64_t began = w->lane ? trace_clock() : 0;
        bool done = render_tile(job, tile, pass, &local, &w->samples_done);
        if (w->lane) trace_tile(job, w->lane, tile, pass, began, done);
        if (!done) break;
        atomic_store(&job->tile_passes[tile], pass + 1);
        if (job->checkpoint) atomic_fetch_add(&job->tiles_done[pass], 1);
        wake_waiters(job);
    }
    // Whoever leaves early releases the waiters: the tiles they wait for may never finish now.
    if (job_stopping(job)) {
        pthread_mutex_lock(&job->lock);
        atomic_store(&job->stopping, 1);
        pthread_cond_broadcast(&job->tile_finished);
        pthread_mutex_unlock(&job->lock);
    }
    w->stats = local;
    trace_set_current(own);
}

static uint64_t samples_so_far(const progress_state *p) {
    uint64_t n = 0;
    for (int i = 0; i < p->worker_count; i++)
        n += atomic_load_explicit(&p->workers[i].samples_done, memory_order_relaxed);
    return n;
}

// Samples per pixel that every pixel has completed: those of the passes every tile has finished.
static int spp_completed(const render_job *job) {
    int passes = job->grid.pass_count;
    for (int i = 0; i < job->grid.tile_count && passes > 0; i++) {
        int p = atomic_load_explicit(&job->tile_passes[i], memory_order_relaxed);
        if (p < passes) passes = p;
    }
    return job->grid.pass_start[passes];
}

// The share of the render's samples done, those a resumed checkpoint brought included.
static double fraction_done(const render_job *job, uint64_t samples) {
    return job->total_samples ? (double)(job->resumed_samples + samples) / (double)job->total_samples : 1.0;
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
        double fraction = fraction_done(p->job, samples_so_far(p));
        if (p->fn) p->fn(fraction, p->user);
        if (p->live_image) p->live_image(p->job->film.image, spp_completed(p->job), fraction, p->live_user);
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

// Sets up the job's passes (from `first` samples: tiles_init), tiles and film over the (checked) region; false when
// out of memory.
static bool job_init(render_job *job, const glint_scene *s, const integrator *it, const int region[4], unsigned aovs,
                     int first) {
    const render_settings *rs = &s->settings;
    memset(job, 0, sizeof *job);
    job->scene = s;
    job->integrator = it;
    memcpy(job->region, region, sizeof job->region);
    tiles_init(&job->grid, region, rs->spp, first);
    job->total_samples =
        (uint64_t)(region[2] - region[0]) * (uint64_t)(region[3] - region[1]) * (uint64_t)rs->spp;
    atomic_init(&job->next_item, 0);
    atomic_init(&job->waiters, 0);
    atomic_init(&job->stopping, 0);
    atomic_init(&job->failed, 0);
    for (int p = 0; p < MAX_PASSES; p++) {
        atomic_init(&job->pass_decision[p], 0);
        atomic_init(&job->tiles_done[p], 0);
        atomic_init(&job->pass_began[p], 0);
        atomic_init(&job->pass_ended[p], 0);
    }
    if (!film_init(&job->film, region, rs->width, rs->height, rs->spp, job->grid.pass_count, rs->transform, aovs))
        return false;
    job->tile_passes = malloc((size_t)job->grid.tile_count * sizeof *job->tile_passes);
    if (!job->tile_passes) {
        film_release(&job->film);
        return false;
    }
    for (int i = 0; i < job->grid.tile_count; i++) atomic_init(&job->tile_passes[i], 0);
    pthread_mutex_init(&job->lock, NULL);
    pthread_cond_init(&job->tile_finished, NULL);
    return true;
}

static void job_free(render_job *job) {
    pthread_cond_destroy(&job->tile_finished);
    pthread_mutex_destroy(&job->lock);
    free(job->tile_passes);
    free(job->counts);
    film_release(&job->film);
}

// Prepares the job's checkpoints and resume (opt->checkpoint, opt->resume): the render's identity, every
// pixel's count, the film's sums kept after every pass, and the resumed checkpoint's samples in the film.
static glint_status job_prepare_checkpoints(render_job *job, const glint_scene *s, const render_options *opt,
                                            glint_error *err) {
    // Before the render, not after it: a checkpoint that cannot be read or written must not cost a render. The
    // file to resume from first, as input: a directory, FIFO or device there is bad usage, and never replaced.
    glint_status st = opt->resume ? checkpoint_check_readable(opt->resume, err) : GLINT_OK;
    if (st == GLINT_OK && opt->checkpoint) st = image_check_file(opt->checkpoint, err);
    if (st != GLINT_OK) return st;
    bool light_sampling = !opt->integrator.no_light_sampling;
    st = checkpoint_identity_of(s, job->region, light_sampling, &job->identity, err);
    if (st != GLINT_OK) return st;
    size_t pixels = (size_t)job->film.image->width * (size_t)job->film.image->height;
    if (!job->counts) job->counts = calloc(pixels, sizeof *job->counts);
    if (!job->counts || !film_keep_all_sums(&job->film)) {
        snprintf(err->message, sizeof err->message, "out of memory for the sums of a %dx%d image",
                 job->film.image->width, job->film.image->height);
        return GLINT_ERR_RENDER;
    }
    job->checkpoint = opt->checkpoint;
    job->gated = opt->checkpoint != NULL; // a pass waits for the previous one only to be written
    if (!opt->resume) return GLINT_OK;
    checkpoint_plane planes[] = {{"count", CHECKPOINT_U32, 1, job->counts},
                                 {"rgb", CHECKPOINT_F64, 3, job->film.sums},
                                 {"rgb_odd", CHECKPOINT_F64, 3, job->film.odd_sums}};
    size_t plane_count = job->film.odd_sums ? 3 : 2;
    int made_for = 0;
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    st = checkpoint_read(opt->resume, &job->identity, planes, plane_count, &made_for, err);
    if (lane)
        trace_add(lane, &(trace_event){"checkpoint read", "io", began, trace_clock(), 1, {{"file", 0, opt->resume}}});
    if (st != GLINT_OK) return st;
    uint32_t most = 0;
    uint64_t total = 0;
    for (size_t i = 0; i < pixels; i++) {
        most = job->counts[i] > most ? job->counts[i] : most;
        total += job->counts[i];
        const double *sum = &job->film.sums[i * 3u], *odd = job->film.odd_sums ? &job->film.odd_sums[i * 3u] : sum;
        if (job->counts[i] == 0 && (sum[0] != 0.0 || sum[1] != 0.0 || sum[2] != 0.0 || odd[0] != 0.0 ||
                                    odd[1] != 0.0 || odd[2] != 0.0)) {
            snprintf(err->message, sizeof err->message, "%s: corrupt checkpoint (pixel %zu has sums but no samples), "
                     "expected a file written by glint's --checkpoint", opt->resume, i);
            return GLINT_ERR_INPUT;
        }
    }
    // Samples cannot be taken back: the mean of fewer is another sum.
    if (most > (uint32_t)s->settings.spp) {
        snprintf(err->message, sizeof err->message, "%s: the checkpoint has pixels of %u samples (it was made for "
                 "%d spp), more than this render's %d; expected --spp %u or more", opt->resume, most, made_for,
                 s->settings.spp, most);
        return GLINT_ERR_INPUT;
    }
    job->resumed_samples = total;
    film_restore_means(&job->film, job->counts);
    return GLINT_OK;
}

// Gives the render's other threads rows of the calling thread's trace, "worker 1", ... (the caller is worker 0),
// and a row for the sample passes; in this order, so that their thread ids are too. Nothing when not traced.
static trace_lane *trace_open_lanes(worker *workers, int threads) {
    trace_lane *lane = trace_current();
    workers[0].lane = lane;
    if (!lane) return NULL;
    for (int i = 1; i < threads; i++) {
        char name[32];
        snprintf(name, sizeof name, "worker %d", i);
        workers[i].lane = trace_lane_open(trace_lane_owner(lane), name);
    }
    return trace_lane_open(trace_lane_owner(lane), "sample passes");
}

// "pass" on the passes' row: from its first tile's start to its last tile's end, for the passes that began.
static void trace_passes(const render_job *job, trace_lane *passes) {
    int complete = job->grid.pass_count;
    for (int i = 0; i < job->grid.tile_count; i++) {
        int p = atomic_load(&job->tile_passes[i]);
        complete = p < complete ? p : complete;
    }
    for (int p = 0; p < job->grid.pass_count; p++) {
        int64_t began = atomic_load(&job->pass_began[p]), ended = atomic_load(&job->pass_ended[p]);
        if (began == 0) continue;
        trace_add(passes, &(trace_event){"pass", "render", began, ended, 4,
                                         {{"pass", p, NULL}, {"first sample", job->grid.pass_start[p], NULL},
                                          {"samples", tiles_pass_samples(&job->grid, p), NULL},
                                          {"complete", p < complete, NULL}}});
    }
}

static glint_status render_run(const glint_scene *s, const render_options *opt, render_progress_fn progress,
                               void *user, glint_image **out, render_stats *stats, glint_error *err);

// The render, as one "render" event on the calling thread's row of the trace when there is one.
glint_status render_scene(const glint_scene *s, const render_options *opt, render_progress_fn progress, void *user,
                          glint_image **out, render_stats *stats, glint_error *err) {
    trace_lane *lane = trace_current();
    int64_t began = lane ? trace_clock() : 0;
    glint_status st = render_run(s, opt, progress, user, out, stats, err);
    if (lane)
        trace_add(lane, &(trace_event){"render", "render", began, trace_clock(), 4,
                                       {{"width", s->settings.width, NULL}, {"height", s->settings.height, NULL},
                                        {"spp", s->settings.spp, NULL}, {"status", st, NULL}}});
    return st;
}

// Runs the render's workers as the items of one job of a thread pool (the calling thread is one of its threads;
// without a pool, no memory for one, it runs them one after the other: slower, the same image), with the progress
// reporter beside them; their counters summed into *total. The threads that ran them; 0 when out of memory.
static int run_workers(render_job *job, int threads, const render_options *opt, render_progress_fn progress,
                       void *user, thread_stats *total) {
    worker *workers = aligned_alloc(64, sizeof(worker) * (size_t)threads);
    if (!workers) return 0;
    memset(workers, 0, sizeof(worker) * (size_t)threads);
    for (int i = 0; i < threads; i++) {
        workers[i].job = job;
        atomic_init(&workers[i].samples_done, 0);
    }
    trace_lane *passes_lane = trace_open_lanes(workers, threads);
    render_live_fn live_image = opt ? opt->live_image : NULL;
    progress_state prog = {.job = job, .workers = workers, .worker_count = threads, .fn = progress, .user = user,
                           .live_image = live_image, .live_user = opt ? opt->live_user : NULL};
    pthread_t prog_thread;
    bool prog_running = (progress || live_image) && progress_start(&prog, &prog_thread);
    thread_pool *pool = thread_pool_start(threads);
    if (pool) thread_pool_run(pool, (size_t)threads, worker_main, workers);
    else
        for (int i = 0; i < threads; i++) worker_main(workers, (size_t)i);
    int ran_on = pool ? thread_pool_size(pool) : 1;
    thread_pool_stop(pool);
    if (prog_running) progress_stop(&prog, prog_thread);
    if (passes_lane) trace_passes(job, passes_lane);
    for (int i = 0; i < threads; i++) {
        total->rays += workers[i].stats.rays;
        total->shadow_rays += workers[i].stats.shadow_rays;
        total->discarded_samples += workers[i].stats.discarded_samples;
        total->samples += workers[i].stats.samples;
    }
    free(workers);
    return ran_on;
}

// The counters of a finished (or stopped) render.
static void fill_stats(render_stats *stats, const thread_stats *total, const render_job *job, const accel *a,
                       double t0, double t_built, int ran_on) {
    memset(stats, 0, sizeof *stats);
    stats->rays = total->rays;
    stats->shadow_rays = total->shadow_rays;
    stats->discarded_samples = total->discarded_samples;
    stats->samples = total->samples;
    stats->samples_resumed = job->resumed_samples;
    accel_stats as;
    accel_get_stats(a, &as);
    stats->bvh_nodes = as.nodes;
    stats->bvh_leaves = as.leaves;
    stats->bvh_depth = as.depth;
    stats->build_seconds = as.build_seconds > 0 ? as.build_seconds : t_built - t0;
    double t_end = clock_seconds();
    stats->wall_seconds = t_end - t0;
    stats->render_seconds = t_end - t_built;
    stats->threads = ran_on;
}

// Whether every pixel has all its samples (`done` samples in all, resumed ones included): spp of them, or fewer where
// adaptive sampling stopped it.
static bool job_complete(const render_job *job, uint64_t done) {
    if (!(job->noise_threshold > 0.0f)) return done == job->total_samples;
    size_t pixels = (size_t)job->film.image->width * (size_t)job->film.image->height;
    for (size_t i = 0; i < pixels; i++)
        if (pixel_needs(job, i, (uint32_t)job->film.spp)) return false;
    return true;
}

// The samples per pixel every pixel has once the workers stopped (`done` samples in all, resumed ones included):
// spp when all were taken (`complete`); under a time limit, which ends the render after a whole pass, the count
// every pixel reached (*timed_out; with adaptive sampling, every pixel it has not stopped); 0 when a stop left
// pixels at different counts.
static int spp_reached(const render_job *job, int spp, uint64_t done, bool complete, bool *timed_out) {
    int passes_run = job->grid.pass_count;
    for (int p = 1; job->deadline > 0.0 && p < job->grid.pass_count; p++)
        if (atomic_load(&job->pass_decision[p]) == PASS_SKIP) {
            passes_run = p;
            break;
        }
    uint64_t pixels = job->total_samples / (uint64_t)spp; // of the region rendered
    // Every pixel at the same count: with counts kept (a resumed render may start from any), that count.
    int uniform = job->grid.pass_start[passes_run];
    bool same = done == pixels * (uint64_t)uniform;
    if (job->counts && job->noise_threshold > 0.0f) {
        uint32_t most = 0;
        for (uint64_t i = 0; i < pixels; i++) most = job->counts[i] > most ? job->counts[i] : most;
        same = true;
        for (uint64_t i = 0; i < pixels && same; i++) same = job->counts[i] == most || !pixel_needs(job, i, most);
        uniform = (int)most;
    } else if (job->counts) {
        same = true;
        for (uint64_t i = 1; i < pixels && same; i++) same = job->counts[i] == job->counts[0];
        uniform = (int)job->counts[0];
    }
    *timed_out = passes_run < job->grid.pass_count && same;
    return complete ? spp : *timed_out ? uniform : 0;
}

static glint_status render_run(const glint_scene *s, const render_options *opt, render_progress_fn progress,
                               void *user, glint_image **out, render_stats *stats, glint_error *err) {
    *out = NULL;
    double t0 = clock_seconds();
    int region[4];
    glint_status st = tiles_resolve_region(&s->settings, opt ? opt->region : NULL, region, err);
    if (st != GLINT_OK) return st;
    unsigned aovs = opt ? opt->aovs : 0u;
    if (aovs & ~FILM_AOV_MASK_ALL) {
        snprintf(err->message, sizeof err->message, "--aov: unknown AOV bits 0x%x, expected GLINT_AOV_ALBEDO, "
                 "GLINT_AOV_NORMAL, GLINT_AOV_DEPTH or GLINT_AOV_SAMPLES", aovs & ~FILM_AOV_MASK_ALL);
        return GLINT_ERR_INPUT;
    }
    // Checkpoints hold the colour's sums: AOVs are not saved in them (yet), so the two do not go together.
    if (aovs && opt && (opt->checkpoint || opt->resume)) {
        snprintf(err->message, sizeof err->message, "--aov cannot be combined with --checkpoint or --resume: "
                 "checkpoints keep the colour's sums only");
        return GLINT_ERR_INPUT;
    }
    // The job, and the checkpoint it resumes, before the frame: a wrong checkpoint must not wait for a BVH.
    render_job job;
    // Passes from one sample where someone watches the image fill or a time limit may stop it early.
    bool watched = opt && (opt->live_image || opt->time_limit > 0.0);
    if (!job_init(&job, s, NULL, region, aovs, watched ? 1 : TILES_FIRST_PASS)) {
        snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image", region[2] - region[0],
                 region[3] - region[1]);
        return GLINT_ERR_RENDER;
    }
    job.cancel = opt ? opt->cancel : NULL;
    // Adaptive sampling: every pixel's count, its sums kept after every pass, and its odd-numbered samples' sums.
    job.noise_threshold = s->settings.noise_threshold;
    if (job.noise_threshold > 0.0f) {
        size_t pixels = (size_t)(region[2] - region[0]) * (size_t)(region[3] - region[1]);
        job.counts = calloc(pixels, sizeof *job.counts);
        if (!job.counts || !film_keep_all_sums(&job.film) || !film_keep_odd_sums(&job.film)) {
            job_free(&job);
            snprintf(err->message, sizeof err->message, "out of memory for the sums of a %dx%d image",
                     region[2] - region[0], region[3] - region[1]);
            return GLINT_ERR_RENDER;
        }
    }
    if (opt && (opt->checkpoint || opt->resume)) {
        st = job_prepare_checkpoints(&job, s, opt, err);
        if (st != GLINT_OK) {
            job_free(&job);
            return st;
        }
    }
    int threads = opt && opt->threads > 0 ? opt->threads : thread_pool_online_cpus();
    if (threads > MAX_THREADS) threads = MAX_THREADS;
    render_frame frame;
    accel_build_options build = opt ? opt->accel : (accel_build_options){0};
    build.threads = threads;
    build.stop = job.cancel;
    st = frame_build(&frame, s, opt ? &opt->integrator : NULL, &build, err);
    if (st == GLINT_ERR_INTERRUPTED) { // stopped while the BVH was built: no sample, a black image
        // A checkpoint is written however the render ends: here the samples it resumed, or none (a stop that came
        // early on a loaded machine once left no file to resume from).
        if (job.checkpoint) job_write_checkpoint(&job);
        glint_status failed = atomic_load(&job.failed) ? GLINT_ERR_RENDER : GLINT_OK;
        if (failed) *err = job.failure;
        job_free(&job);
        if (failed) return failed;
        if (stats) memset(stats, 0, sizeof *stats);
        film f;
        if (!film_init(&f, region, s->settings.width, s->settings.height, 1, 1, s->settings.transform, aovs)) {
            snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image", region[2] - region[0],
                     region[3] - region[1]);
            return GLINT_ERR_RENDER;
        }
        *out = film_take_image(&f);
        return st;
    }
    if (st != GLINT_OK) {
        job_free(&job);
        return st;
    }
    job.integrator = frame.integrator;
    double t_built = clock_seconds();

    if (opt && opt->time_limit > 0.0) {
        job.deadline = t_built + opt->time_limit;
        job.gated = true;
    }
    thread_stats total = {0};
    int ran_on = run_workers(&job, threads, opt, progress, user, &total);
    if (ran_on == 0) {
        job_free(&job);
        frame_release(&frame);
        snprintf(err->message, sizeof err->message, "out of memory for a %dx%d image on %d threads",
                 region[2] - region[0], region[3] - region[1], threads);
        return GLINT_ERR_RENDER;
    }
    render_live_fn live_image = opt ? opt->live_image : NULL;
    uint64_t done = job.resumed_samples + total.samples;
    bool complete = job_complete(&job, done);
    double fraction = complete ? 1.0 : fraction_done(&job, total.samples);
    if (progress) progress(fraction, user);
    // Every worker has stopped: this call sees the image as it will be returned.
    if (live_image) live_image(job.film.image, spp_completed(&job), fraction, opt->live_user);
    if (stats) fill_stats(stats, &total, &job, frame.accel, t0, t_built, ran_on);
    bool timed_out = false;
    int spp_done = spp_reached(&job, s->settings.spp, done, complete, &timed_out);
    if (stats) stats->spp = s->settings.spp;
    if (stats) stats->spp_done = spp_done;
    frame_release(&frame);
    // The last checkpoint, whatever ended the render; none after a failed one (its message is the error).
    if (job.checkpoint && !atomic_load(&job.failed)) job_write_checkpoint(&job);
    if (atomic_load(&job.failed)) {
        *err = job.failure;
        job_free(&job);
        return GLINT_ERR_RENDER;
    }
    *out = film_take_image(&job.film);
    job_free(&job);
    if (!complete && !timed_out) {
        snprintf(err->message, sizeof err->message, "interrupted after %llu of %llu samples",
                 (unsigned long long)done, (unsigned long long)job.total_samples);
        return GLINT_ERR_INTERRUPTED;
    }
    return GLINT_OK;
}
