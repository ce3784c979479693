// cli.h — the command-line program's parts: argument parsing, the progress bar and the statistics line.
#ifndef GLINT_CLI_H
#define GLINT_CLI_H

#include "glint.h"

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

enum { CLI_AOV_COUNT = 4 }; ///< albedo, normal, depth, samples: the bits of glint_aov, in order

/// Everything the command line asked for.
typedef struct cli_options {
    const char *scene_path; ///< "-" reads the scene from standard input
    const char *output;     ///< NULL until cli_parse fills in the default
    char default_output[4096];
    glint_overrides overrides;
    int threads;            ///< 0 = all online CPUs
    long time_limit;        ///< seconds after which no new sample pass starts; 0: none
    int region[4];          ///< --region X0,Y0,X1,Y1; all zero: the whole image
    unsigned aovs;          ///< --aov: glint_aov bits; 0: none
    /// With a .pfm output and --aov: the file of AOV i (bit 1 << i): NAME.albedo.pfm, NAME.normal.pfm,
    /// NAME.depth.pfm; "" for the AOVs not asked for and for an .exr output, which holds them as channels.
    char aov_output[CLI_AOV_COUNT][4096];
    const char *checkpoint; ///< --checkpoint FILE (the --resume file when only that is given), or NULL
    const char *resume;     ///< --resume FILE, or NULL
    const char *trace;      ///< --trace FILE: the timeline of the threads' work, as Chrome trace-event JSON; or NULL
    bool quiet, ascii_ppm, half;
    bool preview;           ///< --preview: show the image in a window as it converges
} cli_options;

/// A program built on this command line (glint, glint-mpi): its name in messages ("NAME: ...", "NAME X.Y.Z")
/// and its own parts of --help around the options they share.
typedef struct cli_program {
    const char *name;
    const char *usage;    ///< the usage lines and what the program does, before the options
    const char *stopping; ///< what signals do, after the options
    const char *notes;    ///< anything more, at the end
    bool silent;          ///< print nothing at all (glint-mpi's ranks other than 0 parse the same arguments)
} cli_program;

/// The glint program.
extern const cli_program CLI_GLINT;

/// What main does after parsing: render, or exit at once with this code.
typedef enum cli_action { CLI_RUN = -1, CLI_EXIT_OK = 0, CLI_EXIT_USAGE = 2 } cli_action;

/// Runs `glint merge OUT PART...` (argv[1] is "merge"): returns the exit status, messages on stderr.
int cli_merge(int argc, char **argv);

/// Parses argv into *o; prints --help/--version to stdout and errors (prefixed "NAME: ") to stderr.
cli_action cli_parse(const cli_program *p, int argc, char **argv, cli_options *o);

/// Reads standard input as a scene (at most GLINT_MAX_SCENE_BYTES): the text and its length, or NULL with the
/// message in *err and the status in *st (GLINT_ERR_RENDER when memory runs out).
char *cli_read_stdin(size_t *length, glint_status *st, glint_error *err);
/// Loads the scene file at `path`, or from standard input for "-" (named "<stdin>" in messages); large meshes
/// are read on `threads` threads (0: all online CPUs).
glint_status cli_load_scene(const char *path, int threads, glint_scene **scene, glint_error *err);
/// Whether the output would replace the scene file (the same file by device and inode, whatever the names).
bool cli_output_is_scene(const char *output, const char *scene_path);

/// The state of the progress bar drawn on stderr.
typedef struct cli_progress {
    double start;   ///< monotonic seconds when the render began
    bool drawn;     ///< a bar is on the screen and must be erased
    double last_time, last_fraction; ///< the previous report (last_time 0: none yet)
    double measured; ///< seconds of rendering the rate was measured over
    double rate;     ///< smoothed fraction of the work done per second
    FILE *stream;    ///< where the bar is drawn: NULL for stderr
} cli_progress;

/// Monotonic clock in seconds.
double cli_now(void);
/// glint_progress_fn drawing "[####----]  42%  1.2 s elapsed, ETA 1.7 s" over itself on stderr, within the
/// terminal's width.
void cli_progress_draw(double fraction, void *user);
/// Erases the bar, if one was drawn.
void cli_progress_clear(cli_progress *p);
/// Ends a finished render's bar: drawn once more at 100 % and left on its line (nothing when none was drawn).
void cli_progress_finish(cli_progress *p);
/// Prints the one-line statistics summary of a render on stderr, naming the image (output NULL: none written)
/// and, when write_seconds >= 0, how long writing it took.
void cli_print_stats(const cli_program *p, const glint_render_stats *st, const char *output, double write_seconds);
/// Says on stderr that the render was interrupted and how many samples per pixel (of img's pixels) are written.
void cli_print_interrupted(const cli_program *prog, const glint_image *img, uint64_t samples, const char *output);
/// Share of a render's samples that may be NaN or infinite (and dropped) before the program exits 1: 1 %.
#define CLI_MAX_DISCARDED_SHARE 0.01
/// Warns on stderr (even with --quiet) when st dropped samples; true when more than CLI_MAX_DISCARDED_SHARE did.
bool cli_warn_discarded(const cli_program *p, const glint_render_stats *st);

#endif
