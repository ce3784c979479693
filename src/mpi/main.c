// main.c — glint-mpi: glint's render on every process of an MPI job. Every rank reads the scene and builds
// its own render frame; rank 0 hands out tile passes (farm.c), renders its share, writes the image and prints
// what glint prints; the image is glint's, byte for byte, for any number of ranks and threads.
#include "accel/accel.h"
#include "cli/cli.h"
#include "cli/signals.h"
#include "core/clock.h"
#include "film/film.h"
#include "mpi/farm.h"
#include "render/frame.h"
#include "render/tiles.h"
#include "scene/scene.h"

#include <inttypes.h>
#include <mpi.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const cli_program CLI_MPI = {
    .name = "glint-mpi",
    .usage = "usage: mpirun [-np N] glint-mpi [options] SCENE\n"
             "\n"
             "Renders the JSON scene file SCENE on every process (rank) of an MPI job and writes the image\n"
             "from rank 0: the same image, byte for byte, as glint's with the same options, for any number\n"
             "of ranks and threads. Rank 0 hands out the passes of 16x16 tiles as ranks free up, renders\n"
             "too, and prints the progress and statistics. Every rank reads SCENE and the files it names\n"
             "itself, at the same path (a shared file system); - reads the scene from rank 0's standard\n"
             "input and sends it to the others. Options are glint's and apply to every rank; --threads\n"
             "counts the threads of each rank (0, the default: the CPUs the rank may run on, which\n"
             "mpirun may restrict: use mpirun --bind-to none or --map-by node:PE=N).\n",
    .stopping = "Ctrl-C to mpirun (Open MPI then sends SIGTERM to every rank, and SIGKILL a second later), or\n"
                "SIGINT, SIGTERM or SIGHUP to any rank, stops the render on every rank: rank 0 writes the\n"
                "image of the tile passes completed so far. A rank that cannot read the scene ends the job\n"
                "with its message; a rank that dies ends it too (the launcher stops the others).\n",
    .notes = "\n"
             "docs/distributed.md: clusters, hostfiles, threads per rank, faults, and render farms without MPI.\n",
};

static atomic_int stopping; // polled before every sample: set by a signal (cli/signals.c), or by the farm
static bool speaks;         // rank 0 without --quiet: prints the signal messages

// Whether the launcher that started this process (mpirun, when rank 0 runs on its node) writes its standard
// output to a terminal. mpirun gives a rank a pseudo-terminal for standard output even when its own output
// goes to a file, and a pipe for standard error; so rank 0 draws the bar on standard output, which mpirun
// forwards, only when that ends on a terminal, and a batch job's log gets no bar.
static bool launcher_on_terminal(void) {
    char link[64], target[64];
    snprintf(link, sizeof link, "/proc/%ld/fd/1", (long)getppid());
    ssize_t n = readlink(link, target, sizeof target - 1);
    if (n <= 0) return false;
    target[n] = '\0';
    return isatty(STDOUT_FILENO) && (strncmp(target, "/dev/pts/", 9) == 0 || strncmp(target, "/dev/tty", 8) == 0);
}

static int exit_code(glint_status st) { return st == GLINT_ERR_INPUT ? 2 : 1; }

// Ends the MPI job of this rank and returns its exit status.
static int leave(int code) {
    MPI_Finalize();
    return code;
}

// The scene on every rank: read from its path by each, or from rank 0's standard input and broadcast.
static glint_status load_scene(const char *path, int rank, int threads, glint_scene **scene, glint_error *err) {
    glint_load_options lo = {.threads = threads};
    if (strcmp(path, "-") != 0) return glint_scene_load_with(path, &lo, scene, err);
    long long length = -1; // -1: rank 0 could not read it (its message is in its *err)
    size_t n = 0;
    glint_status st = GLINT_OK;
    char *text = rank == 0 ? cli_read_stdin(&n, &st, err) : NULL;
    if (text) {
        length = (long long)n;
        st = GLINT_OK;
    }
    MPI_Bcast(&length, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    if (length < 0) {
        if (rank != 0) snprintf(err->message, sizeof err->message, "rank 0 could not read the scene");
        return rank == 0 ? st : GLINT_ERR_INPUT;
    }
    if (rank != 0 && !(text = malloc((size_t)length + 1))) {
        snprintf(err->message, sizeof err->message, "out of memory for the scene");
        st = GLINT_ERR_RENDER;
    }
    // Every rank takes part in the broadcast; one without memory receives into a byte and fails after it.
    char byte;
    for (long long at = 0; at < length; at += 1 << 30) {
        int chunk = length - at < (1 << 30) ? (int)(length - at) : 1 << 30;
        MPI_Bcast(text ? text + at : &byte, text ? chunk : 0, MPI_CHAR, 0, MPI_COMM_WORLD);
    }
    if (st == GLINT_OK) st = glint_scene_parse_with("<stdin>", text, (size_t)length, &lo, scene, err);
    free(text);
    return st;
}

// Whether every rank is ready; if not, the first failing rank's message is printed by rank 0 (the rank named
// when it is not 0) and *code is the exit status every rank leaves with.
static bool all_ready(glint_status st, const glint_error *err, int rank, int size, bool quiet, int *code) {
    int failing = st == GLINT_OK ? size : rank, first = size;
    MPI_Allreduce(&failing, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == size) return true;
    struct {
        int status, signal;
        char host[MPI_MAX_PROCESSOR_NAME];
        char message[sizeof err->message];
    } why;
    memset(&why, 0, sizeof why);
    if (rank == first) {
        why.status = (int)st;
        why.signal = atomic_load(cli_signals_first());
        int len = 0;
        MPI_Get_processor_name(why.host, &len);
        memcpy(why.message, err->message, sizeof why.message);
    }
    MPI_Bcast(&why, (int)sizeof why, MPI_BYTE, first, MPI_COMM_WORLD);
    if (why.status == GLINT_ERR_INTERRUPTED) { // a signal while the frame was built: nothing rendered anywhere
        if (rank == 0 && !quiet)
            fprintf(stderr, "glint-mpi: interrupted before any sample was rendered, no image written\n");
        *code = 128 + (why.signal ? why.signal : SIGINT);
        return false;
    }
    if (rank == 0) {
        if (first == 0) fprintf(stderr, "glint-mpi: %s\n", why.message);
        else fprintf(stderr, "glint-mpi: rank %d (%s): %s\n", first, why.host, why.message);
    }
    *code = exit_code((glint_status)why.status);
    return false;
}

// What rank 0 checks before anything is read: the output can be written and is not the scene file.
static glint_status check_output(const cli_options *opt, glint_format format, glint_error *err) {
    glint_status st = glint_image_check_path(opt->output, format, err);
    if (st != GLINT_OK) return st;
    if (cli_output_is_scene(opt->output, opt->scene_path)) {
        snprintf(err->message, sizeof err->message, "%s: cannot write: it is the scene file, which would be lost",
                 opt->output);
        return GLINT_ERR_INPUT;
    }
    return GLINT_OK;
}

// The per-rank shares and the traffic between ranks, after glint's statistics line.
static void print_shares(const farm_report *r, int size, double seconds) {
    fprintf(stderr, "glint-mpi: %d rank%s; units (tile passes) and samples per rank:", size, size == 1 ? "" : "s");
    uint64_t units = 0;
    for (int i = 0; i < size; i++) units += r->shares[i].units;
    for (int i = 0; i < size; i++) {
        const farm_share *s = &r->shares[i];
        double share = r->total.samples ? 100.0 * (double)s->samples / (double)r->total.samples : 0.0;
        fprintf(stderr, "%s %d: %" PRIu64 " units, %" PRIu64 " samples (%.1f %%, %d thread%s)", i ? "," : "", i,
                s->units, s->samples, share, s->threads, s->threads == 1 ? "" : "s");
    }
    fputc('\n', stderr);
    uint64_t messages = r->messages_sent + r->messages_received, bytes = r->bytes_sent + r->bytes_received;
    double per_unit = r->units_remote ? (double)bytes / (double)r->units_remote : 0.0;
    // What a model of more ranks needs: bytes per unit, messages per second, rank 0's time per unit.
    fprintf(stderr,
            "glint-mpi: traffic of rank 0: %" PRIu64 " messages (%.0f/s), %" PRIu64 " bytes sent, %" PRIu64
            " received, %.0f bytes per unit rendered elsewhere (%" PRIu64 " of %" PRIu64 "); busy %.1f ms, "
            "%.1f us per unit\n",
            messages, seconds > 0 ? (double)messages / seconds : 0.0, r->bytes_sent, r->bytes_received, per_unit,
            r->units_remote, units, r->busy_seconds * 1e3, units ? r->busy_seconds * 1e6 / (double)units : 0.0);
}

// The job's statistics, as glint's statistics line gives them, from rank 0's report and clock.
static glint_render_stats job_stats(const farm_report *report, const accel *a, double t0, double t_built,
                                    double t_end, int all_threads, int spp) {
    glint_render_stats stats;
    memset(&stats, 0, sizeof stats);
    stats.samples = report->total.samples;
    stats.rays = report->total.rays;
    stats.shadow_rays = report->total.shadow_rays;
    stats.discarded_samples = report->total.discarded_samples;
    accel_stats as;
    accel_get_stats(a, &as);
    stats.bvh_nodes = as.nodes;
    stats.bvh_leaves = as.leaves;
    stats.bvh_depth = as.depth;
    stats.build_seconds = as.build_seconds > 0 ? as.build_seconds : t_built - t0;
    stats.wall_seconds = t_end - t0;
    stats.render_seconds = t_end - t_built;
    stats.threads = all_threads;
    stats.spp = spp;
    return stats;
}

// Rank 0's end of the job: the statistics, the warnings, the image written. The exit status.
static int finish_master(const cli_program *prog, const cli_options *opt, glint_format format,
                         const farm_report *report, const glint_render_stats *stats, const glint_image *img, int size,
                         bool interrupted) {
    glint_error err;
    int code;
    if (!opt->quiet) {
        cli_print_stats(prog, stats, interrupted && stats->samples == 0 ? NULL : opt->output, -1.0);
        print_shares(report, size, stats->render_seconds);
    }
    bool lost = cli_warn_discarded(prog, stats);
    if (!interrupted && stats->spp_done < stats->spp && !opt->quiet)
        fprintf(stderr, "glint-mpi: time limit of %ld s reached: %d of %d samples per pixel rendered\n",
                opt->time_limit, stats->spp_done, stats->spp);
    int sig = report->stop_signal > 0 ? report->stop_signal : SIGINT;
    if (interrupted && !opt->quiet && report->stopped_by != 0)
        fprintf(stderr, "glint-mpi: rank %d was stopped by signal %d\n", report->stopped_by, sig);
    if (interrupted && stats->samples == 0) {
        if (!opt->quiet) fprintf(stderr, "glint-mpi: interrupted before any sample was rendered, no image written\n");
        code = 128 + sig;
    } else {
        if (interrupted && !opt->quiet) cli_print_interrupted(prog, img, stats->samples, opt->output);
        if (strcmp(opt->output, "-") != 0) cli_signals_block();
        glint_status st = glint_image_write(img, opt->output, format, &err);
        if (st != GLINT_OK) fprintf(stderr, "glint-mpi: %s\n", err.message);
        code = st != GLINT_OK ? exit_code(st) : interrupted ? 128 + sig : lost ? 1 : 0;
    }
    return code;
}

int main(int argc, char **argv) {
    int provided = 0;
    // Only each process's main thread calls MPI; the render threads never do.
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "glint-mpi: MPI cannot start\n");
        return 1;
    }
    // Errors come back as values: a rank that has died is reported, not a crash of the others.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (provided < MPI_THREAD_FUNNELED) {
        if (rank == 0) fprintf(stderr, "glint-mpi: this MPI library does not support threads (MPI_THREAD_FUNNELED)\n");
        return leave(1);
    }

    // Every rank parses the same arguments; rank 0 alone speaks, and all leave alike on --help or an error.
    cli_program prog = CLI_MPI;
    prog.silent = rank != 0;
    cli_options opt;
    cli_action action = cli_parse(&prog, argc, argv, &opt);
    if (action != CLI_RUN) return leave((int)action);
    // Options of the glint program that the ranks' protocol does not carry (yet): refused, not ignored.
    const char *unsupported = opt.aovs ? "--aov" : opt.preview ? "--preview" : opt.resume ? "--resume"
                              : opt.checkpoint ? "--checkpoint" : opt.trace ? "--trace" : NULL;
    if (unsupported) {
        if (rank == 0) fprintf(stderr, "glint-mpi: %s is not supported by glint-mpi (use glint)\n", unsupported);
        return leave(2);
    }
    speaks = rank == 0 && !opt.quiet;
    glint_format format = opt.ascii_ppm ? GLINT_FORMAT_PPM_ASCII : opt.half ? GLINT_FORMAT_EXR_HALF : GLINT_FORMAT_AUTO;

    glint_error err;
    glint_status st = rank == 0 ? check_output(&opt, format, &err) : GLINT_OK;
    cli_signals_install("glint-mpi", !speaks, NULL, &stopping);
    glint_scene *scene = NULL;
    // A scene from standard input is broadcast: every rank takes part even when rank 0's output is refused.
    if (st == GLINT_OK || strcmp(opt.scene_path, "-") == 0) {
        glint_status loaded = load_scene(opt.scene_path, rank, opt.threads > 0 ? opt.threads : glint_cpu_count(), &scene, &err);
        if (st == GLINT_OK) st = loaded;
    }
    cli_signals_loaded();
    if (st == GLINT_OK) st = glint_scene_override(scene, &opt.overrides, &err);
    if (st == GLINT_OK && rank == 0 && glint_scene_reads_file(scene, opt.output)) {
        snprintf(err.message, sizeof err.message,
                 "%s: cannot write: the scene reads it (a mesh, texture or environment map), which would be lost",
                 opt.output);
        st = GLINT_ERR_INPUT;
    }
    // Adaptive sampling's per-pixel counts and half-buffers are not in the ranks' messages (yet): refused.
    if (st == GLINT_OK && scene->settings.noise_threshold > 0.0f) {
        snprintf(err.message, sizeof err.message, "adaptive sampling (--noise-threshold, \"noise_threshold\") is not "
                 "supported by glint-mpi (use glint, or a threshold of 0)");
        st = GLINT_ERR_INPUT;
    }
    int region[4];
    if (st == GLINT_OK) st = tiles_resolve_region(&scene->settings, opt.region, region, &err);
    int threads = opt.threads > 0 ? opt.threads : glint_cpu_count();
    if (threads > 256) threads = 256;
    render_frame frame = {0};
    double t0 = clock_seconds(); // glint's wall time starts here too: the frame build and the render
    accel_build_options build = {.threads = threads, .stop = &stopping};
    if (st == GLINT_OK) st = frame_build(&frame, scene, NULL, &build, &err);
    int code = 0;
    if (!all_ready(st, &err, rank, size, opt.quiet, &code)) {
        frame_release(&frame);
        glint_scene_free(scene);
        return leave(code);
    }
    for (size_t i = 0; speaks && i < glint_scene_warning_count(scene); i++)
        fprintf(stderr, "glint-mpi: %s\n", glint_scene_warning(scene, i));

    const render_settings *rs = &scene->settings;
    tiles grid;
    tiles_init(&grid, region, rs->spp, opt.time_limit > 0 ? 1 : TILES_FIRST_PASS); // as glint cuts it
    int *rank_threads = rank == 0 ? malloc((size_t)size * sizeof *rank_threads) : NULL;
    int all_threads = threads;
    MPI_Gather(&threads, 1, MPI_INT, rank_threads, 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (int i = 1; rank == 0 && i < size; i++) all_threads += rank_threads[i];
    if (speaks)
        fprintf(stderr, "glint-mpi: rendering %dx%d pixels, %d samples each, on %d rank%s with %d threads\n",
                region[2] - region[0], region[3] - region[1], rs->spp, size, size == 1 ? "" : "s", all_threads);

    double t_built = clock_seconds();
    cli_progress bar = {.start = cli_now(), .drawn = false};
    bool bar_on_stderr = isatty(STDERR_FILENO);
    if (!bar_on_stderr && launcher_on_terminal() && strcmp(opt.output, "-") != 0) bar.stream = stdout;
    farm_setup setup = {.rank = rank, .size = size, .grid = &grid, .integrator = frame.integrator,
                        .stop = &stopping, .signal = cli_signals_first(), .threads = threads,
                        .rank_threads = rank_threads,
                        .deadline = opt.time_limit > 0 ? t_built + (double)opt.time_limit : 0.0,
                        .progress = speaks && (bar_on_stderr || bar.stream) ? cli_progress_draw : NULL, .user = &bar};
    if (rank != 0) {
        bool ok = farm_worker(&setup);
        frame_release(&frame);
        glint_scene_free(scene);
        if (!ok) MPI_Abort(MPI_COMM_WORLD, 1);
        int sig = atomic_load(cli_signals_first());
        return leave(sig ? 128 + sig : 0);
    }

    film f;
    farm_report report;
    memset(&report, 0, sizeof report);
    if (!film_init(&f, region, rs->width, rs->height, rs->spp, grid.pass_count, rs->transform, 0u)) {
        snprintf(err.message, sizeof err.message, "out of memory for a %dx%d image", region[2] - region[0],
                 region[3] - region[1]);
        st = GLINT_ERR_RENDER;
    } else {
        st = farm_master(&setup, &f, &report, &err);
    }
    cli_progress_clear(&bar);
    if (st != GLINT_OK && st != GLINT_ERR_INTERRUPTED) {
        fprintf(stderr, "glint-mpi: %s\n", err.message);
        film_release(&f);
        frame_release(&frame);
        glint_scene_free(scene);
        MPI_Abort(MPI_COMM_WORLD, exit_code(st)); // the other ranks may be waiting for work that will not come
        return exit_code(st);
    }
    double t_end = clock_seconds();

    glint_render_stats stats = job_stats(&report, frame.accel, t0, t_built, t_end, all_threads, rs->spp);
    bool interrupted = st == GLINT_ERR_INTERRUPTED;
    stats.spp_done = interrupted ? 0 : grid.pass_start[report.passes_done];
    frame_release(&frame);
    glint_scene_free(scene);
    free(rank_threads);
    glint_image *img = film_take_image(&f);
    film_release(&f);

    code = finish_master(&prog, &opt, format, &report, &stats, img, size, interrupted);
    glint_image_free(img);
    bool finished = farm_master_finish(&setup, &report, 10.0);
    farm_report_free(&report);
    if (!finished) {
        fprintf(stderr, "glint-mpi: a rank did not finish within 10 s of the end of the render; aborting the job\n");
        MPI_Abort(MPI_COMM_WORLD, code ? code : 1);
    }
    return leave(code);
}
