// farm.c — rank 0 hands out tile passes and assembles the film; the other ranks render what they are given.
// Only each rank's main thread calls MPI, always without blocking (Isend, Irecv and Test), sleeping on its
// crew's results between looks: a rank waiting for work burns no core, and two ranks sending to each other at
// once never wait on each other.
#include "mpi/farm.h"
#include "core/clock.h"
#include "mpi/crew.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum {
    TAG_UNIT = 1, // 0 -> rank: render pass `pass` of tile `tile`; the tile's sums follow unless it is pass 0
    TAG_RESULT,   // rank -> 0: the pass is done; counters in the header, then the sums (unless it was the last
                  // pass) and the means
    TAG_STOP,     // rank -> 0: a signal (header.signal) stopped this rank
    TAG_DONE,     // 0 -> rank: the render is over; header.signal nonzero: stop the units in progress
    TAG_BYE,      // rank -> 0: finished; nothing more will come from this rank
};

// The longest a rank's main thread sleeps between looks at MPI, in seconds: the latency of a message, which
// the queue of units each rank holds (QUEUE_PER_THREAD) hides.
#define POLL_SECONDS 0.001
#define PROGRESS_SECONDS 0.2
enum { QUEUE_PER_THREAD = 2, QUEUE_EXTRA = 2 };

// Every message starts with this header; the arrays follow it unaligned (copied with memcpy).
typedef struct wire {
    int32_t tile, pass, signal, unused;
    uint64_t samples, rays, shadow_rays, discarded;
} wire;

#define MESSAGE_MAX (sizeof(wire) + (size_t)UNIT_MAX_PIXELS * 3 * (sizeof(double) + sizeof(float)))

// Sends not yet known to be complete, with the buffers they send from.
typedef struct outbox {
    MPI_Request *requests;
    unsigned char **buffers;
    int count, capacity;
} outbox;

// What rank 0 keeps between farm_master and farm_master_finish: the other ranks' receives and the sends.
struct farm_link {
    MPI_Request *receives;     ///< one posted receive per rank (index 0 unused): a rank's messages keep their order
    unsigned char **buffers;   ///< their buffers, MESSAGE_MAX bytes each
    bool *gone;                ///< the rank said BYE (its receive is no longer posted)
    outbox out;
};

static void mpi_message(int rc, char *buf, size_t size) {
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    if (MPI_Error_string(rc, text, &len) != MPI_SUCCESS) snprintf(text, sizeof text, "error %d", rc);
    snprintf(buf, size, "%s", text);
}

// Starts a send of `bytes` bytes (copied); false when MPI refuses or memory runs out (message in *err).
static bool post(outbox *o, int dest, int tag, const void *data, size_t bytes, glint_error *err) {
    if (o->count == o->capacity) {
        int cap = o->capacity ? 2 * o->capacity : 16;
        MPI_Request *r = realloc(o->requests, (size_t)cap * sizeof *r);
        if (r) o->requests = r;
        unsigned char **b = r ? realloc(o->buffers, (size_t)cap * sizeof *b) : NULL;
        if (!b) {
            snprintf(err->message, sizeof err->message, "out of memory for the messages to rank %d", dest);
            return false;
        }
        o->buffers = b;
        o->capacity = cap;
    }
    unsigned char *copy = malloc(bytes);
    if (!copy) {
        snprintf(err->message, sizeof err->message, "out of memory for a message to rank %d", dest);
        return false;
    }
    memcpy(copy, data, bytes);
    int rc = MPI_Isend(copy, (int)bytes, MPI_BYTE, dest, tag, MPI_COMM_WORLD, &o->requests[o->count]);
    if (rc != MPI_SUCCESS) {
        free(copy);
        char why[MPI_MAX_ERROR_STRING];
        mpi_message(rc, why, sizeof why);
        snprintf(err->message, sizeof err->message, "MPI cannot send to rank %d: %s", dest, why);
        return false;
    }
    o->buffers[o->count++] = copy;
    return true;
}

// Frees the buffers of the sends that are complete; false (message in *err) when one failed.
static bool outbox_progress(outbox *o, glint_error *err) {
    int kept = 0;
    bool ok = true;
    for (int i = 0; i < o->count; i++) {
        int done = 0;
        MPI_Status status;
        int rc = MPI_Test(&o->requests[i], &done, &status);
        if (rc != MPI_SUCCESS && ok) {
            char why[MPI_MAX_ERROR_STRING];
            mpi_message(rc, why, sizeof why);
            snprintf(err->message, sizeof err->message, "MPI cannot send: %s", why);
            ok = false;
        }
        if (done || rc != MPI_SUCCESS) {
            free(o->buffers[i]);
            continue;
        }
        o->requests[kept] = o->requests[i];
        o->buffers[kept++] = o->buffers[i];
    }
    o->count = kept;
    return ok;
}

static void outbox_free(outbox *o) {
    for (int i = 0; i < o->count; i++) free(o->buffers[i]); // only after the job is over or aborted
    free(o->requests);
    free(o->buffers);
    memset(o, 0, sizeof *o);
}

static int tile_pixels(const tiles *g, int tile) {
    int r[4];
    tiles_rect(g, tile, r);
    return (r[2] - r[0]) * (r[3] - r[1]);
}

// Whether a pass starts from sums (every pass but the first) and leaves sums (every pass but the last).
static bool sums_in(int pass) { return pass > 0; }
static bool sums_out(const tiles *g, int pass) { return pass + 1 < g->pass_count; }

static size_t result_bytes(const tiles *g, int tile, int pass) {
    size_t n = (size_t)tile_pixels(g, tile) * 3;
    return sizeof(wire) + (sums_out(g, pass) ? n * sizeof(double) : 0) + n * sizeof(float);
}

static size_t unit_bytes(const tiles *g, int tile, int pass) {
    return sizeof(wire) + (sums_in(pass) ? (size_t)tile_pixels(g, tile) * 3 * sizeof(double) : 0);
}

static void nap(double seconds) {
    struct timespec ts = {.tv_sec = 0, .tv_nsec = (long)(seconds * 1e9)};
    nanosleep(&ts, NULL);
}

// ---- rank 0 ----

typedef struct master {
    const farm_setup *s;
    const tiles *g;
    film *film;
    farm_report *report;
    struct farm_link *link;
    crew crew;
    int *next_pass;     ///< per tile: passes handed out
    int *done_pass;     ///< per tile: passes whose results are in the film
    int *outstanding;   ///< per rank: units handed out and not back
    int *depth;         ///< per rank: how many units it may hold
    int cursor;         ///< every item before it is handed out
    int items, in_flight;
    int skip_from;      ///< the first pass the time limit skips (pass_count: none)
    bool *decided;      ///< per pass: the time limit let it run
    unsigned char *scratch; ///< MESSAGE_MAX bytes to build a message in
    glint_error *err;
} master;

// The tile's sums (row by row) from the film, or its sums and means into it.
static void film_get_sums(const film *f, const int r[4], double *sums) {
    size_t w = (size_t)(r[2] - r[0]) * 3;
    for (int y = r[1]; y < r[3]; y++, sums += w)
        memcpy(sums, &f->sums[film_pixel_index(f, r[0], y) * 3], w * sizeof *sums);
}

static void film_put(film *f, const int r[4], const double *sums, const float *means) {
    size_t w = (size_t)(r[2] - r[0]) * 3;
    for (int y = r[1]; y < r[3]; y++, means += w) {
        size_t at = film_pixel_index(f, r[0], y) * 3;
        memcpy(&f->image->rgb[at], means, w * sizeof *means);
        if (sums) {
            memcpy(&f->sums[at], sums, w * sizeof *sums);
            sums += w;
        }
    }
}

// The next unit to hand out, in the render loop's order (pass by pass, tile by tile), skipping tiles whose
// previous pass is still out; false when there is none now. Under a time limit, the first unit handed out of
// each pass decides, by the clock, whether that pass runs at all (as the render loop decides).
static bool next_unit(master *m, int *tile, int *pass) {
    int tc = m->g->tile_count;
    while (m->cursor < m->items && m->next_pass[m->cursor % tc] > m->cursor / tc) m->cursor++;
    int end = m->cursor + 2 * tc < m->items ? m->cursor + 2 * tc : m->items; // no further than a pass ahead
    for (int i = m->cursor; i < end; i++) {
        int p = i / tc, t = i % tc;
        if (p >= m->skip_from) return false;
        if (m->next_pass[t] != p || m->done_pass[t] != p) continue;
        if (p > 0 && !m->decided[p]) {
            if (m->s->deadline > 0.0 && clock_seconds() > m->s->deadline) {
                m->skip_from = p;
                return false;
            }
            m->decided[p] = true;
        }
        *tile = t;
        *pass = p;
        return true;
    }
    return false;
}

static bool hand_out(master *m, int rank, int tile, int pass) {
    int r[4];
    tiles_rect(m->g, tile, r);
    if (rank == 0) {
        unit *u = crew_unit_new();
        if (!u) {
            snprintf(m->err->message, sizeof m->err->message, "out of memory for a tile");
            return false;
        }
        u->tile = tile;
        u->pass = pass;
        if (sums_in(pass)) film_get_sums(m->film, r, u->sums);
        crew_give(&m->crew, u);
    } else {
        wire h = {.tile = tile, .pass = pass};
        memcpy(m->scratch, &h, sizeof h);
        if (sums_in(pass)) {
            double sums[UNIT_MAX_PIXELS * 3];
            film_get_sums(m->film, r, sums);
            memcpy(m->scratch + sizeof h, sums, (size_t)tile_pixels(m->g, tile) * 3 * sizeof *sums);
        }
        size_t bytes = unit_bytes(m->g, tile, pass);
        if (!post(&m->link->out, rank, TAG_UNIT, m->scratch, bytes, m->err)) return false;
        m->report->messages_sent++;
        m->report->bytes_sent += bytes;
    }
    m->next_pass[tile] = pass + 1;
    m->outstanding[rank]++;
    m->in_flight++;
    return true;
}

// Fills every rank's queue, one unit per rank in turn, so that the first passes spread over all of them.
static bool dispatch(master *m) {
    for (bool more = true; more;) {
        more = false;
        for (int rank = 0; rank < m->s->size; rank++) {
            if (m->link->gone[rank] || m->outstanding[rank] >= m->depth[rank]) continue;
            int tile, pass;
            if (!next_unit(m, &tile, &pass)) return true;
            if (!hand_out(m, rank, tile, pass)) return false;
            more = true;
        }
    }
    return true;
}

// A finished unit from `rank`: into the film, its counters into the report.
static void accept(master *m, int rank, int tile, int pass, const thread_stats *ts, const double *sums,
                   const float *means) {
    m->outstanding[rank]--;
    m->in_flight--;
    if (tile < 0 || tile >= m->g->tile_count || pass != m->done_pass[tile] || m->next_pass[tile] != pass + 1)
        return; // not a unit this render is waiting for (cannot happen with a well-behaved rank)
    int r[4];
    tiles_rect(m->g, tile, r);
    film_put(m->film, r, sums_out(m->g, pass) ? sums : NULL, means);
    m->done_pass[tile] = pass + 1;
    thread_stats *t = &m->report->total;
    t->samples += ts->samples;
    t->rays += ts->rays;
    t->shadow_rays += ts->shadow_rays;
    t->discarded_samples += ts->discarded_samples;
    m->report->shares[rank].units++;
    m->report->shares[rank].samples += ts->samples;
    if (rank != 0) m->report->units_remote++;
}

static void stop_from(master *m, int rank, int signal) {
    if (m->report->stop_signal) return;
    m->report->stop_signal = signal;
    m->report->stopped_by = rank;
    atomic_store(m->s->stop, 1); // this rank's threads end their units at the next sample
}

// Handles a message from `rank` (its receive is complete) and posts the next receive from it.
static bool receive(master *m, int rank, const MPI_Status *status) {
    struct farm_link *l = m->link;
    int bytes = 0;
    MPI_Get_count(status, MPI_BYTE, &bytes);
    m->report->messages_received++;
    m->report->bytes_received += (uint64_t)bytes;
    wire h;
    memcpy(&h, l->buffers[rank], sizeof h);
    if (status->MPI_TAG == TAG_RESULT) {
        size_t n = h.tile >= 0 && h.tile < m->g->tile_count ? (size_t)tile_pixels(m->g, h.tile) * 3 : 0;
        if (h.pass < 0 || h.pass >= m->g->pass_count || (size_t)bytes != result_bytes(m->g, h.tile, h.pass)) n = 0;
        double sums[UNIT_MAX_PIXELS * 3];
        float means[UNIT_MAX_PIXELS * 3];
        const unsigned char *p = l->buffers[rank] + sizeof h;
        if (n && sums_out(m->g, h.pass)) {
            memcpy(sums, p, n * sizeof *sums);
            p += n * sizeof *sums;
        }
        if (n) memcpy(means, p, n * sizeof *means);
        thread_stats ts = {.samples = h.samples, .rays = h.rays, .shadow_rays = h.shadow_rays,
                           .discarded_samples = h.discarded};
        if (n) accept(m, rank, h.tile, h.pass, &ts, sums, means);
        else {
            m->outstanding[rank]--;
            m->in_flight--;
        }
    } else if (status->MPI_TAG == TAG_STOP) {
        stop_from(m, rank, h.signal);
    } else if (status->MPI_TAG == TAG_BYE) {
        l->gone[rank] = true; // a rank says BYE only after DONE: it is not expected now
        snprintf(m->err->message, sizeof m->err->message, "rank %d left the render early", rank);
        return false;
    }
    int rc = MPI_Irecv(l->buffers[rank], (int)MESSAGE_MAX, MPI_BYTE, rank, MPI_ANY_TAG, MPI_COMM_WORLD,
                       &l->receives[rank]);
    if (rc != MPI_SUCCESS) {
        char why[MPI_MAX_ERROR_STRING];
        mpi_message(rc, why, sizeof why);
        snprintf(m->err->message, sizeof m->err->message, "MPI cannot receive from rank %d: %s", rank, why);
        return false;
    }
    return true;
}

// Looks at every other rank's receive once; false on an MPI failure. *any: a message came.
static bool poll_ranks(master *m, bool *any) {
    for (int rank = 1; rank < m->s->size; rank++) {
        if (m->link->gone[rank]) continue;
        int done = 0;
        MPI_Status status;
        int rc = MPI_Test(&m->link->receives[rank], &done, &status);
        if (rc != MPI_SUCCESS) {
            char why[MPI_MAX_ERROR_STRING];
            mpi_message(rc, why, sizeof why);
            snprintf(m->err->message, sizeof m->err->message, "MPI cannot receive from rank %d: %s", rank, why);
            return false;
        }
        if (!done) continue;
        *any = true;
        if (!receive(m, rank, &status)) return false;
    }
    return true;
}

static bool link_open(struct farm_link *l, int size, glint_error *err) {
    memset(l, 0, sizeof *l);
    l->receives = calloc((size_t)size, sizeof *l->receives);
    l->buffers = calloc((size_t)size, sizeof *l->buffers);
    l->gone = calloc((size_t)size, sizeof *l->gone);
    bool ok = l->receives && l->buffers && l->gone;
    for (int rank = 1; ok && rank < size; rank++) ok = (l->buffers[rank] = malloc(MESSAGE_MAX)) != NULL;
    if (!ok) {
        snprintf(err->message, sizeof err->message, "out of memory for the messages of %d ranks", size);
        return false;
    }
    for (int rank = 1; rank < size; rank++) {
        int rc = MPI_Irecv(l->buffers[rank], (int)MESSAGE_MAX, MPI_BYTE, rank, MPI_ANY_TAG, MPI_COMM_WORLD,
                           &l->receives[rank]);
        if (rc != MPI_SUCCESS) {
            char why[MPI_MAX_ERROR_STRING];
            mpi_message(rc, why, sizeof why);
            snprintf(err->message, sizeof err->message, "MPI cannot receive from rank %d: %s", rank, why);
            return false;
        }
    }
    return true;
}

static void link_free(struct farm_link *l, int size) {
    if (!l) return;
    for (int rank = 1; l->buffers && rank < size; rank++) free(l->buffers[rank]);
    free(l->receives);
    free(l->buffers);
    free(l->gone);
    outbox_free(&l->out);
    free(l);
}

void farm_report_free(farm_report *r) {
    free(r->shares);
    r->shares = NULL;
}

glint_status farm_master(const farm_setup *s, film *f, farm_report *r, glint_error *err) {
    memset(r, 0, sizeof *r);
    const tiles *g = s->grid;
    master m = {.s = s, .g = g, .film = f, .report = r, .err = err, .items = g->tile_count * g->pass_count,
                .skip_from = g->pass_count};
    r->shares = calloc((size_t)s->size, sizeof *r->shares);
    m.link = malloc(sizeof *m.link);
    m.next_pass = calloc((size_t)g->tile_count, sizeof *m.next_pass);
    m.done_pass = calloc((size_t)g->tile_count, sizeof *m.done_pass);
    m.outstanding = calloc((size_t)s->size, sizeof *m.outstanding);
    m.depth = calloc((size_t)s->size, sizeof *m.depth);
    m.decided = calloc((size_t)g->pass_count + 1, sizeof *m.decided);
    m.scratch = malloc(MESSAGE_MAX);
    glint_status st = GLINT_OK;
    if (!r->shares || !m.link || !m.next_pass || !m.done_pass || !m.outstanding || !m.depth || !m.decided ||
        !m.scratch) {
        snprintf(err->message, sizeof err->message, "out of memory for the work of %d ranks", s->size);
        free(m.link);
        m.link = NULL;
        st = GLINT_ERR_RENDER;
    } else if (!link_open(m.link, s->size, err)) {
        st = GLINT_ERR_RENDER;
    } else if (!crew_start(&m.crew, g, s->integrator, s->stop, s->threads)) {
        snprintf(err->message, sizeof err->message, "cannot start a render thread");
        st = GLINT_ERR_RENDER;
    }
    if (st != GLINT_OK) {
        // The other ranks wait for units that will not come: they are aborted with the job.
        link_free(m.link, s->size);
        free(m.next_pass), free(m.done_pass), free(m.outstanding), free(m.depth), free(m.decided), free(m.scratch);
        farm_report_free(r);
        return st;
    }
    for (int rank = 0; rank < s->size; rank++) {
        r->shares[rank].threads = s->rank_threads[rank];
        // Rank 0's own threads get their units without a message's delay: one each and one waiting suffice.
        m.depth[rank] = rank == 0 ? s->rank_threads[rank] + 1
                                  : QUEUE_PER_THREAD * s->rank_threads[rank] + QUEUE_EXTRA;
    }

    double next_progress = clock_seconds() + PROGRESS_SECONDS;
    bool busy = true;
    while (st == GLINT_OK) {
        // Sleep only when the last round found nothing to do; a unit finished here wakes it at once.
        unit *done = crew_take(&m.crew, busy ? 0.0 : POLL_SECONDS);
        double awake = clock_seconds();
        busy = done != NULL;
        while (done) {
            unit *u = done;
            done = u->next;
            if (u->complete) accept(&m, 0, u->tile, u->pass, &u->stats, u->sums, u->means);
            else {
                m.outstanding[0]--;
                m.in_flight--;
            }
            free(u);
        }
        if (!poll_ranks(&m, &busy) || !outbox_progress(&m.link->out, err)) st = GLINT_ERR_RENDER;
        if (st == GLINT_OK && atomic_load(s->stop)) {
            if (!r->stop_signal) stop_from(&m, 0, atomic_load(s->signal));
            st = GLINT_ERR_INTERRUPTED;
        }
        if (st == GLINT_OK && !dispatch(&m)) st = GLINT_ERR_RENDER;
        if (st == GLINT_OK && m.in_flight == 0) break; // nothing out and nothing more to hand out: finished
        if (s->progress && clock_seconds() >= next_progress) {
            uint64_t total = (uint64_t)(g->region[2] - g->region[0]) * (uint64_t)(g->region[3] - g->region[1]) *
                             (uint64_t)g->spp;
            s->progress((double)r->total.samples / (double)total, s->user);
            next_progress = clock_seconds() + PROGRESS_SECONDS;
        }
        r->busy_seconds += clock_seconds() - awake;
    }
    if (st != GLINT_OK) atomic_store(s->stop, 1); // a stop or a failure: this rank's units in progress end now

    // Tell every other rank that the render is over (a nonzero signal: drop what is in progress).
    wire h = {.signal = st == GLINT_OK ? 0 : r->stop_signal ? r->stop_signal : -1};
    glint_error ignored;
    for (int rank = 1; rank < s->size; rank++)
        if (!m.link->gone[rank] && post(&m.link->out, rank, TAG_DONE, &h, sizeof h, &ignored)) {
            r->messages_sent++;
            r->bytes_sent += sizeof h;
        }
    crew_close(&m.crew);

    int passes = g->pass_count;
    for (int t = 0; t < g->tile_count; t++) passes = m.done_pass[t] < passes ? m.done_pass[t] : passes;
    r->passes_done = passes;
    r->link = m.link;
    free(m.next_pass), free(m.done_pass), free(m.outstanding), free(m.depth), free(m.decided), free(m.scratch);
    return st;
}

bool farm_master_finish(const farm_setup *s, farm_report *r, double seconds) {
    struct farm_link *l = r->link;
    if (!l) return s->size == 1;
    double until = clock_seconds() + seconds;
    glint_error err;
    bool ok = true;
    for (;;) {
        int left = 0;
        for (int rank = 1; rank < s->size; rank++) {
            if (l->gone[rank]) continue;
            int done = 0;
            MPI_Status status;
            if (MPI_Test(&l->receives[rank], &done, &status) != MPI_SUCCESS) {
                ok = false;
                break;
            }
            if (done && status.MPI_TAG == TAG_BYE) {
                l->gone[rank] = true;
                continue;
            }
            left++;
            // Results still on their way when the render ended are dropped; the rank's next message is awaited.
            if (done && MPI_Irecv(l->buffers[rank], (int)MESSAGE_MAX, MPI_BYTE, rank, MPI_ANY_TAG, MPI_COMM_WORLD,
                                  &l->receives[rank]) != MPI_SUCCESS) {
                ok = false;
                break;
            }
        }
        ok = outbox_progress(&l->out, &err) && ok;
        if (!ok || (left == 0 && l->out.count == 0) || clock_seconds() > until) break;
        nap(POLL_SECONDS);
    }
    ok = ok && l->out.count == 0;
    for (int rank = 1; rank < s->size; rank++) ok = ok && l->gone[rank];
    // The buffers of receives and sends still pending stay allocated: MPI may write to them until the abort.
    if (ok) link_free(l, s->size);
    r->link = NULL;
    return ok;
}

// ---- the other ranks ----

static bool worker_fail(const farm_setup *s, const char *what) {
    fprintf(stderr, "glint-mpi: rank %d: %s\n", s->rank, what);
    return false;
}

// One loop over the messages a worker rank can receive and the units its crew finishes, kept whole (101 lines):
// its states (waiting, stopping, draining) are easiest to check against farm_master's when read in one place.
bool farm_worker(const farm_setup *s) {
    const tiles *g = s->grid;
    crew c;
    if (!crew_start(&c, g, s->integrator, s->stop, s->threads)) return worker_fail(s, "cannot start a render thread");
    unsigned char *in = malloc(MESSAGE_MAX), *msg = malloc(MESSAGE_MAX);
    outbox out = {0};
    glint_error err;
    MPI_Request receive;
    bool ok = in && msg;
    if (!ok) snprintf(err.message, sizeof err.message, "out of memory for messages");
    if (ok && MPI_Irecv(in, (int)MESSAGE_MAX, MPI_BYTE, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &receive) != MPI_SUCCESS) {
        snprintf(err.message, sizeof err.message, "MPI cannot receive from rank 0");
        ok = false;
    }
    bool stop_sent = false, busy = true;
    while (ok) {
        unit *done = crew_take(&c, busy ? 0.0 : POLL_SECONDS);
        busy = done != NULL;
        while (done) {
            unit *u = done;
            done = u->next;
            if (u->complete && ok) { // a unit cut short by a stop is dropped: rank 0 keeps the tile's last pass
                size_t n = (size_t)tile_pixels(g, u->tile) * 3;
                wire h = {.tile = u->tile, .pass = u->pass, .samples = u->stats.samples, .rays = u->stats.rays,
                          .shadow_rays = u->stats.shadow_rays, .discarded = u->stats.discarded_samples};
                unsigned char *p = msg;
                memcpy(p, &h, sizeof h);
                p += sizeof h;
                if (sums_out(g, u->pass)) {
                    memcpy(p, u->sums, n * sizeof *u->sums);
                    p += n * sizeof *u->sums;
                }
                memcpy(p, u->means, n * sizeof *u->means);
                p += n * sizeof *u->means;
                ok = post(&out, 0, TAG_RESULT, msg, (size_t)(p - msg), &err);
            }
            free(u);
        }
        int signal = atomic_load(s->signal);
        if (ok && signal && !stop_sent) { // stopped here: rank 0 stops the others and writes what it has
            wire h = {.signal = signal};
            ok = post(&out, 0, TAG_STOP, &h, sizeof h, &err);
            stop_sent = true;
        }
        int arrived = 0;
        MPI_Status status;
        if (ok && MPI_Test(&receive, &arrived, &status) != MPI_SUCCESS) {
            snprintf(err.message, sizeof err.message, "MPI cannot receive from rank 0");
            ok = false;
        }
        if (ok && arrived) {
            busy = true;
            wire h;
            memcpy(&h, in, sizeof h);
            if (status.MPI_TAG == TAG_DONE) {
                if (h.signal) atomic_store(s->stop, 1);
                break;
            }
            unit *u = status.MPI_TAG == TAG_UNIT ? crew_unit_new() : NULL;
            if (u) {
                u->tile = h.tile;
                u->pass = h.pass;
                if (sums_in(h.pass))
                    memcpy(u->sums, in + sizeof h, (size_t)tile_pixels(g, h.tile) * 3 * sizeof *u->sums);
                crew_give(&c, u);
            } else if (status.MPI_TAG == TAG_UNIT) {
                snprintf(err.message, sizeof err.message, "out of memory for a tile");
                ok = false;
            }
            if (ok &&
                MPI_Irecv(in, (int)MESSAGE_MAX, MPI_BYTE, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &receive) != MPI_SUCCESS) {
                snprintf(err.message, sizeof err.message, "MPI cannot receive from rank 0");
                ok = false;
            }
        }
        if (ok) ok = outbox_progress(&out, &err);
    }
    crew_close(&c);
    if (ok) {
        wire h = {0};
        ok = post(&out, 0, TAG_BYE, &h, sizeof h, &err);
    }
    // Every message delivered before MPI_Finalize (rank 0 receives until every rank's BYE); a rank 0 that is
    // gone is noticed by the launcher, which ends the job.
    double until = clock_seconds() + 10.0;
    while (ok && out.count > 0 && clock_seconds() < until) {
        ok = outbox_progress(&out, &err);
        if (out.count > 0) nap(POLL_SECONDS);
    }
    if (ok && out.count > 0) {
        snprintf(err.message, sizeof err.message, "rank 0 has not taken the last messages for 10 s");
        ok = false;
    }
    free(msg);
    if (ok) {
        free(in);
        outbox_free(&out);
        return true;
    }
    return worker_fail(s, err.message); // the buffers MPI may still use stay allocated until the abort
}
