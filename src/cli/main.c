// main.c — the glint command: parse flags, load the scene, render with a progress bar, write the image;
// SIGINT/SIGTERM/SIGHUP stop the render and keep the samples completed so far.
#include "cli.h"
#include "glint.h"
#include "preview.h"
#include "signals.h"

#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static const char NOTHING_RENDERED[] = "glint: interrupted before any sample was rendered, no image written\n";

static int exit_code(glint_status st) { return st == GLINT_ERR_INPUT ? 2 : 1; }

// One call of glint_render: on the main thread, or on a thread of its own while a preview window has the main one.
typedef struct render_call {
    const glint_scene *scene;
    const glint_render_options *options;
    glint_progress_fn progress;
    void *user;
    glint_image *image;
    glint_render_stats stats;
    glint_error err;
    glint_status status;
    glint_trace *trace; ///< the render's thread records into it (NULL: no trace)
} render_call;

static void render_call_run(void *arg) {
    render_call *c = arg;
    // A no-op on the main thread, which is attached already; the preview's render thread gets a row of its own.
    if (c->trace && glint_trace_attach(c->trace, "render", &c->err) != GLINT_OK) {
        c->status = GLINT_ERR_RENDER;
        return;
    }
    c->status = glint_render(c->scene, c->options, c->progress, c->user, &c->image, &c->stats, &c->err);
}

// The preview window for the image the render will make (NULL when there is none to be had); none for a region
// the render will refuse, so that its message comes alone.
static cli_preview *open_preview(const cli_options *opt, const glint_scene *scene) {
    int w, h;
    glint_scene_size(scene, &w, &h);
    const int *r = opt->region;
    if (r[2] > 0) {
        if (r[2] > w || r[3] > h) return NULL;
        w = r[2] - r[0];
        h = r[3] - r[1];
    }
    const char *base = strrchr(opt->scene_path, '/');
    const char *name = strcmp(opt->scene_path, "-") == 0 ? "standard input" : base ? base + 1 : opt->scene_path;
    return cli_preview_open(name, w, h, opt->quiet);
}

// Why `path` (--checkpoint, --trace) cannot be written: one of the files the render reads or writes, which
// would be lost; NULL when it is none of them.
static const char *clobbers(const char *path, const cli_options *opt, const char *const *outputs, int output_count) {
    int images = 1; // the image and its AOV files come first, then the region files beside them
    for (int i = 0; i < CLI_AOV_COUNT; i++) images += opt->aov_output[i][0] != '\0';
    for (int i = 0; i < output_count; i++)
        if (glint_path_same_target(path, outputs[i]))
            return i == 0 ? "the output image" : i < images ? "an AOV file" : "a region file";
    if (cli_output_is_scene(path, opt->scene_path)) return "the scene file";
    return NULL;
}

// Every file the render will write (the image, the AOV files beside a PFM, the region files beside a region's
// PFMs, the checkpoint, the trace) checked before the render, not after it: a typo in -o must not cost a long
// render. Fills outputs (the image, AOV and region files, *count of them, at most 2 * (1 + CLI_AOV_COUNT));
// -1 when all is well, else the exit status, the message printed.
static int check_outputs(const cli_options *opt, glint_format format, const char **outputs, int *count) {
    glint_error err;
    int output_count = 0;
    outputs[output_count++] = opt->output;
    for (int i = 0; i < CLI_AOV_COUNT; i++)
        if (opt->aov_output[i][0]) outputs[output_count++] = opt->aov_output[i];
    int images = output_count;
    // A region's PFM (and each AOV PFM beside it) is followed by NAME.pfm.region, that glint merge places it by.
    static char region_files[1 + CLI_AOV_COUNT][sizeof opt->aov_output[0] + sizeof ".region"];
    size_t out_len = strlen(opt->output);
    bool pfm = out_len > 4 && strcasecmp(opt->output + out_len - 4, ".pfm") == 0;
    for (int i = 0; pfm && opt->region[2] > 0 && i < images; i++) {
        snprintf(region_files[i], sizeof region_files[i], "%s.region", outputs[i]);
        outputs[output_count++] = region_files[i];
    }
    *count = output_count;
    for (int i = 0; i < output_count; i++) {
        glint_status st = i < images ? glint_image_check_path(outputs[i], i == 0 ? format : GLINT_FORMAT_PFM, &err)
                                     : GLINT_OK;
        if (st != GLINT_OK) {
            fprintf(stderr, "glint: %s\n", err.message);
            return exit_code(st);
        }
        if (cli_output_is_scene(outputs[i], opt->scene_path)) {
            fprintf(stderr, "glint: %s: cannot write: it is the scene file, which would be lost\n", outputs[i]);
            return exit_code(GLINT_ERR_INPUT);
        }
    }
    const char *clobbered = opt->checkpoint ? clobbers(opt->checkpoint, opt, outputs, output_count) : NULL;
    if (clobbered) {
        fprintf(stderr, "glint: --checkpoint: %s: cannot write: it is %s, which would be lost\n", opt->checkpoint,
                clobbered);
        return exit_code(GLINT_ERR_INPUT);
    }
    if (opt->trace) {
        glint_status st = glint_trace_check_path(opt->trace, &err);
        if (st != GLINT_OK) {
            fprintf(stderr, "glint: --trace: %s\n", err.message);
            return exit_code(st);
        }
        clobbered = clobbers(opt->trace, opt, outputs, output_count);
        if (!clobbered && opt->checkpoint && glint_path_same_target(opt->trace, opt->checkpoint)) clobbered = "the checkpoint";
        if (!clobbered && opt->resume && glint_path_same_target(opt->trace, opt->resume)) clobbered = "the checkpoint";
        if (clobbered) {
            fprintf(stderr, "glint: --trace: %s: cannot write: it is %s, which would be lost\n", opt->trace, clobbered);
            return exit_code(GLINT_ERR_INPUT);
        }
    }
    return -1;
}

// The scene, read and overridden, that writes none of the files it reads; -1 when all is well (*out holds it),
// else the exit status, the message printed.
static int load_scene(const cli_options *opt, glint_cancel *cancel, const char *const *outputs, int output_count,
                      glint_scene **out) {
    glint_error err;
    cli_signals_install("glint", opt->quiet, cancel, NULL);
    glint_scene *scene = NULL;
    glint_status st = cli_load_scene(opt->scene_path, opt->threads, &scene, &err);
    cli_signals_loaded();
    if (st == GLINT_OK) st = glint_scene_override(scene, &opt->overrides, &err);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        glint_scene_free(scene);
        return exit_code(st);
    }
    // Nor any other file the scene was read from: a mesh, a texture, an environment map.
    for (int i = 0; i < output_count; i++)
        if (glint_scene_reads_file(scene, outputs[i])) {
            fprintf(stderr, "glint: %s: cannot write: the scene reads it (a mesh, texture or environment map), which "
                            "would be lost\n", outputs[i]);
            glint_scene_free(scene);
            return exit_code(GLINT_ERR_INPUT);
        }
    for (int i = 0; i < 2; i++) {
        const char *flag = i == 0 ? "--checkpoint" : "--trace", *path = i == 0 ? opt->checkpoint : opt->trace;
        if (path && glint_scene_reads_file(scene, path)) {
            fprintf(stderr, "glint: %s: %s: cannot write: the scene reads it (a mesh, texture or environment map), "
                            "which would be lost\n", flag, path);
            glint_scene_free(scene);
            return exit_code(GLINT_ERR_INPUT);
        }
    }
    // The library never prints: what it worked around in mesh files is reported here, unless --quiet.
    for (size_t i = 0; !opt->quiet && i < glint_scene_warning_count(scene); i++)
        fprintf(stderr, "glint: %s\n", glint_scene_warning(scene, i));
    if (atomic_load(cli_signals_first())) { // stopped before the render began: there is nothing to write
        glint_scene_free(scene);
        if (!opt->quiet) fprintf(stderr, "%s", NOTHING_RENDERED);
        return cli_signals_status();
    }
    *out = scene;
    return -1;
}

// Everything after the command line: load, render, write the image and the trace (NULL: none); the exit status.
static int run(const cli_options *opt, glint_trace *trace, glint_cancel *cancel) {
    glint_error err;
    glint_format format = opt->ascii_ppm ? GLINT_FORMAT_PPM_ASCII
                          : opt->half    ? GLINT_FORMAT_EXR_HALF
                                         : GLINT_FORMAT_AUTO;
    const char *outputs[2 * (1 + CLI_AOV_COUNT)];
    int output_count = 0;
    int code = check_outputs(opt, format, outputs, &output_count);
    if (code >= 0) return code;
    glint_scene *scene = NULL;
    code = load_scene(opt, cancel, outputs, output_count, &scene);
    if (code >= 0) return code;
    glint_status st;

    cli_progress bar = {.start = cli_now(), .drawn = false};
    bool show_progress = !opt->quiet && isatty(STDERR_FILENO);
    glint_render_options ropt = {.threads = opt->threads, .time_limit = (double)opt->time_limit};
    memcpy(ropt.region, opt->region, sizeof ropt.region);
    ropt.aovs = opt->aovs;
    ropt.checkpoint = opt->checkpoint;
    ropt.resume = opt->resume;
    ropt.cancel = cancel; // the signal handler's, and the preview window's
    cli_preview *preview = opt->preview ? open_preview(opt, scene) : NULL;
    if (preview) {
        ropt.live_image = cli_preview_live_image;
        ropt.live_user = preview;
    }
    render_call call = {.scene = scene, .options = &ropt, .progress = show_progress ? cli_progress_draw : NULL,
                        .user = &bar, .trace = trace};
    if (preview) cli_preview_run(preview, render_call_run, &call, cancel);
    else render_call_run(&call);
    glint_image *img = call.image;
    glint_render_stats stats = call.stats;
    err = call.err;
    st = call.status;
    glint_scene_free(scene);
    if (st == GLINT_OK) cli_progress_finish(&bar); // the bar says 100 % where the render reached it
    else cli_progress_clear(&bar);
    // Only a finished render keeps its window: a stopped one was stopped to end the program.
    if (st != GLINT_OK) {
        cli_preview_close(preview);
        preview = NULL;
    }
    if (st != GLINT_OK && st != GLINT_ERR_INTERRUPTED) {
        fprintf(stderr, "glint: %s\n", err.message);
        glint_image_free(img);
        return exit_code(st);
    }
    bool interrupted = st == GLINT_ERR_INTERRUPTED;
    uint64_t samples_kept = stats.samples + stats.samples_resumed; // a resumed render keeps what it resumed
    if (interrupted && samples_kept == 0) {
        if (!opt->quiet) cli_print_stats(&CLI_GLINT, &stats, NULL, -1.0);
        if (!opt->quiet) fprintf(stderr, "%s", NOTHING_RENDERED);
        glint_image_free(img);
        return cli_signals_status();
    }
    if (interrupted && !opt->quiet) cli_print_interrupted(&CLI_GLINT, img, samples_kept, opt->output);

    if (strcmp(opt->output, "-") != 0) cli_signals_block();
    double write_began = cli_now();
    st = glint_image_write(img, opt->output, format, &err);
    for (int i = 0; st == GLINT_OK && i < CLI_AOV_COUNT; i++)
        if (opt->aov_output[i][0]) st = glint_image_write_aov(img, (glint_aov)(1u << i), opt->aov_output[i], &err);
    // The statistics once the image is written, with how long that took (a 4K EXR takes seconds).
    if (st == GLINT_OK && !opt->quiet) cli_print_stats(&CLI_GLINT, &stats, opt->output, cli_now() - write_began);
    // A render that lost more than a small share of its samples is wrong, but its image is still written.
    bool lost = st == GLINT_OK && cli_warn_discarded(&CLI_GLINT, &stats);
    if (st == GLINT_OK && !interrupted && stats.spp_done < stats.spp && !opt->quiet)
        fprintf(stderr, "glint: time limit of %ld s reached: %d of %d samples per pixel rendered\n", opt->time_limit,
                stats.spp_done, stats.spp);
    if (st != GLINT_OK) {
        fprintf(stderr, "glint: %s\n", err.message);
        glint_image_free(img);
        cli_preview_close(preview);
        return exit_code(st);
    }
    // The trace last, so that it shows the image being written.
    if (trace) {
        cli_signals_block(); // a rename never races an abort (standard output left them unblocked)
        st = glint_trace_write(trace, opt->trace, &err);
        if (st != GLINT_OK) {
            fprintf(stderr, "glint: --trace: %s\n", err.message);
            glint_image_free(img);
            cli_preview_close(preview);
            return interrupted ? cli_signals_status() : exit_code(st);
        }
    }
    if (cli_preview_is_open(preview)) { // the image is written; the window stays until the user closes it
        if (!opt->quiet) fprintf(stderr, "glint: the preview window stays open until it is closed (or Esc)\n");
        char status[128];
        snprintf(status, sizeof status, "done, %d spp - Esc closes", stats.spp_done);
        cli_signals_unblock();
        cli_preview_hold(preview, img, status, cli_signals_first());
    }
    glint_image_free(img);
    cli_preview_close(preview);
    if (atomic_load(cli_signals_first())) return cli_signals_status(); // Ctrl-C while the window waited
    return interrupted ? cli_signals_status() : lost ? 1 : 0;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "merge") == 0) return cli_merge(argc, argv);
    cli_options opt;
    cli_action action = cli_parse(&CLI_GLINT, argc, argv, &opt);
    if (action != CLI_RUN) return (int)action;
    glint_trace *trace = NULL;
    if (opt.trace) {
        glint_error err;
        trace = glint_trace_new();
        if (!trace || glint_trace_attach(trace, "main", &err) != GLINT_OK) {
            fprintf(stderr, "glint: --trace: out of memory for the trace\n");
            glint_trace_free(trace);
            return exit_code(GLINT_ERR_RENDER);
        }
    }
    glint_cancel *cancel = glint_cancel_new();
    int status = cancel ? run(&opt, trace, cancel) : exit_code(GLINT_ERR_RENDER);
    if (!cancel) fprintf(stderr, "glint: out of memory\n");
    cli_signals_block(); // no handler may use the token once it is freed
    glint_cancel_free(cancel);
    glint_trace_free(trace);
    return status;
}
