// farm.h — glint-mpi's work between ranks. Rank 0 hands out units (one sample pass of one 16x16 tile, in the
// render loop's order: every tile's pass 0, then pass 1, ...) to every rank as its render threads free up,
// itself included, sending a tile's running sums with its next pass; the ranks send back the new sums and
// means, which rank 0 stores in its film. A pixel's sums thus add its samples in index order whoever renders
// them, and the image is glint's, byte for byte.
#ifndef GLINT_MPI_FARM_H
#define GLINT_MPI_FARM_H

#include "glint.h"
#include "core/stats.h"
#include "film/film.h"
#include "integrator/integrator.h"
#include "render/tiles.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

/// What one rank did: its threads, and the units and samples it rendered that are in the image.
typedef struct farm_share {
    int threads;
    uint64_t units, samples;
} farm_share;

/// What the farm needs from the program; the same on every rank but `threads` (rank 0 gets every rank's).
typedef struct farm_setup {
    int rank, size;
    const tiles *grid;
    const integrator *integrator;
    atomic_int *stop;          ///< the process's stop flag: a signal handler sets it; the farm sets it too
    const atomic_int *signal;  ///< the signal that stopped this process, 0 while none has
    int threads;               ///< this rank's render threads
    const int *rank_threads;   ///< rank 0: every rank's render threads
    double deadline;           ///< rank 0: clock_seconds() after which no pass starts (0: no time limit)
    glint_progress_fn progress; ///< rank 0: hears the fraction of samples done (may be NULL)
    void *user;
} farm_setup;

/// What rank 0 reports after the render.
typedef struct farm_report {
    thread_stats total;        ///< the counters of the units in the image
    farm_share *shares;        ///< one per rank (farm_master allocates them; free with farm_report_free)
    int passes_done;           ///< passes every tile completed
    int stop_signal;           ///< the signal that stopped the render on some rank, 0 if none did
    int stopped_by;            ///< the rank the stop came from
    uint64_t units_remote;     ///< units rendered by ranks other than 0
    uint64_t messages_sent, messages_received; ///< by rank 0, to and from the other ranks
    uint64_t bytes_sent, bytes_received;
    double busy_seconds;       ///< time rank 0's main thread spent handling units and messages (not waiting)
    struct farm_link *link;    ///< the messages still in flight, for farm_master_finish
} farm_report;

/// Rank 0: renders the grid's units on every rank into f (a film of the grid's region with its sums), until
/// every unit is done, the time limit skips a pass, a signal stops it here or on another rank, or MPI fails
/// (GLINT_ERR_RENDER, message in *err). Then tells the other ranks it is over (farm_master_finish waits for
/// them); its own threads have ended. GLINT_ERR_INTERRUPTED when a signal stopped it: f then holds every
/// tile's last completed pass.
glint_status farm_master(const farm_setup *s, film *f, farm_report *r, glint_error *err);
/// Rank 0, after the image is written: waits up to `seconds` for every other rank to say it has finished
/// (their last results are dropped); false when one did not (the caller then aborts the job).
bool farm_master_finish(const farm_setup *s, farm_report *r, double seconds);
/// Frees what a report holds.
void farm_report_free(farm_report *r);

/// Ranks other than 0: renders the units rank 0 sends until it says the render is over. False when MPI
/// failed (a message on stderr).
bool farm_worker(const farm_setup *s);

#endif
