// args.c — glint's command line: a table of options read by getopt_long, strict integer values, --help and --version.
#include "cli.h"

#include <errno.h>
#include <stdarg.h>
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

typedef enum option_id {
    OPT_OUTPUT, OPT_ASCII_PPM, OPT_HALF, OPT_TIME_LIMIT, OPT_WIDTH, OPT_HEIGHT, OPT_SPP, OPT_DEPTH, OPT_SEED,
    OPT_THREADS, OPT_ACCEL, OPT_SAMPLER, OPT_NOISE_THRESHOLD, OPT_OUTPUT_ENCODING, OPT_REGION, OPT_AOV, OPT_PREVIEW, OPT_CHECKPOINT, OPT_RESUME,
    OPT_TRACE, OPT_QUIET, OPT_HELP, OPT_VERSION
} option_id;

typedef struct option_spec {
    const char *long_name;
    char short_name;     ///< 0 when there is none
    bool takes_value;
    option_id id;
    long long min, max;  ///< range of an integer value (min > max: not an integer)
} option_spec;

// The ranges are the scene file's limits (docs/scene-format.md); glint_scene_override checks them again.
static const option_spec OPTIONS[] = {
    {"output", 'o', true, OPT_OUTPUT, 1, 0},
    {"ascii-ppm", 0, false, OPT_ASCII_PPM, 1, 0},
    {"half", 0, false, OPT_HALF, 1, 0},
    {"width", 0, true, OPT_WIDTH, 1, 16384},
    {"height", 0, true, OPT_HEIGHT, 1, 16384},
    {"spp", 0, true, OPT_SPP, 1, 1000000},
    {"depth", 0, true, OPT_DEPTH, 0, 10000},
    {"seed", 0, true, OPT_SEED, 0, 9007199254740992LL}, // 2^53: every seed a JSON number holds exactly
    {"threads", 0, true, OPT_THREADS, 0, 256}, // 0: all online CPUs, as the library counts them
    {"time-limit", 0, true, OPT_TIME_LIMIT, 1, 100000000},
    {"accel", 0, true, OPT_ACCEL, 1, 0},
    {"sampler", 0, true, OPT_SAMPLER, 1, 0},
    {"noise-threshold", 0, true, OPT_NOISE_THRESHOLD, 1, 0},
    {"output-encoding", 0, true, OPT_OUTPUT_ENCODING, 1, 0},
    {"region", 0, true, OPT_REGION, 1, 0},
    {"aov", 0, true, OPT_AOV, 1, 0},
    {"preview", 0, false, OPT_PREVIEW, 1, 0},
    {"checkpoint", 0, true, OPT_CHECKPOINT, 1, 0},
    {"resume", 0, true, OPT_RESUME, 1, 0},
    {"trace", 0, true, OPT_TRACE, 1, 0},
    {"quiet", 'q', false, OPT_QUIET, 1, 0},
    {"help", 'h', false, OPT_HELP, 1, 0},
    {"version", 'V', false, OPT_VERSION, 1, 0},
};
enum { OPTION_COUNT = sizeof OPTIONS / sizeof OPTIONS[0] };

const cli_program CLI_GLINT = {
    .name = "glint",
    .usage = "usage: glint [options] SCENE\n"
             "       glint merge OUT PART...\n"
             "\n"
             "Renders the JSON scene file SCENE (- reads it from standard input) and writes the image.\n"
             "Options override the scene file's \"render\" settings.\n"
             "glint merge assembles the files of regions (--region) into the full image OUT, with the\n"
             "parts' values unchanged; they must tile it exactly: no overlap, no gap. 8-bit PNG parts merge\n"
             "to .png or .ppm; float parts (OpenEXR, placed by their data windows, or PFM, placed by the\n"
             "PART.region file glint writes beside each) to .exr (every channel), .pfm or .hdr (the colour).\n"
             "8-bit and float parts together, or an output of the other kind, are refused (exit 2).\n"
             "(To render a scene file named merge, write ./merge.)\n",
    .stopping = "Ctrl-C (SIGINT), SIGTERM or SIGHUP stops the render within a second and writes the image\n"
                "rendered so far (each pixel the mean of its completed samples; nothing if no sample was\n"
                "completed); a second Ctrl-C aborts at once. While the scene is read, it stops at once.\n",
    .notes = "",
};

// The program's messages: "NAME: what went wrong", unless it parses silently (glint-mpi's ranks but 0).
__attribute__((format(printf, 2, 3))) static void say(const cli_program *prog, const char *format, ...) {
    if (prog->silent) return;
    va_list ap;
    va_start(ap, format);
    fprintf(stderr, "%s: ", prog->name);
    vfprintf(stderr, format, ap);
    va_end(ap);
}

static void print_usage(const cli_program *prog, FILE *f) {
    if (prog->silent) return;
    int cpus = glint_cpu_count();
    fputs(prog->usage, f);
    fprintf(f,
            "\n"
            "options:\n"
            "  -o, --output FILE  the image to write; its extension chooses the format:\n"
            "                     .png (8-bit RGB), .ppm (binary P6), .pfm (linear float RGB),\n"
            "                     .exr (OpenEXR, linear float RGB), .hdr (Radiance RGBE, linear);\n"
            "                     - writes PPM to standard output. Default: the scene's file name with\n"
            "                     .png, in the current directory (scenes/paper.json -> paper.png;\n"
            "                     out.png when the scene comes from standard input). A symbolic link is\n"
            "                     written through; the scene file and read-only files are never replaced\n"
            "      --ascii-ppm    write PPM as ASCII P3, as the seeds print it, instead of binary P6\n"
            "      --half         write EXR channels as 16-bit halves instead of 32-bit floats\n"
            "      --width N      image width in pixels, 1..16384\n"
            "      --height N     image height in pixels, 1..16384\n"
            "      --spp N        samples per pixel, 1..1000000\n"
            "      --depth N      maximum recursion (Whitted) or bounce (path) depth, 0..10000\n"
            "      --seed N       random seed, 0..9007199254740992 (2^53)\n"
            "      --threads N    worker threads of the render, the BVH build and mesh reading, 0..256; 0 and\n"
            "                     the default: every CPU glint may run on (%d here); 1 renders sequentially. The\n"
            "                     image (and the BVH, and the meshes read) is the same for every N\n"
            "      --time-limit S no sample pass starts after S seconds, 1..100000000: the image is that of\n"
            "                     the samples per pixel reached (1, 2, 4, ...; said on stderr), exit 0\n"
            "      --output-encoding E  how .png and .ppm encode linear values: linear, gamma2 or srgb\n"
            "                     (default: the scene's \"output\"; without it srgb, linear in paper mode)\n"
            "      --accel KIND   acceleration structure: bvh, bvh2 or none (brute force: every ray tests\n"
            "                     every object and triangle; a warning says so when there are meshes)\n"
            "      --sampler S    the path tracer's random numbers: sobol (Owen-scrambled Sobol', the\n"
            "                     default) or independent (PCG32); the Whitted integrators ignore it\n"
            "      --noise-threshold T  adaptive sampling, 0..1000 (0: off): after each sample pass a pixel\n"
            "                     of 16 samples or more whose estimated relative error (its two half-buffers'\n"
            "                     difference, Cycles' measure) is below T takes no more samples (0.01: fine)\n"
            "      --region X0,Y0,X1,Y1\n"
            "                     render only the pixels X0 <= x < X1, Y0 <= y < Y1, each exactly as in the\n"
            "                     full image; the image written is (X1-X0)x(Y1-Y0) and records where it lies\n"
            "                     for glint merge: a PNG in a glint:region text chunk, an OpenEXR as its data\n"
            "                     window, a PFM in the file NAME.pfm.region written beside it\n",
            cpus);
    // In parts: ISO C promises string literals of 4095 bytes, no more.
    fprintf(f,
            "      --aov LIST     also render AOVs, a comma-separated list of albedo, normal, depth and\n"
            "                     samples: the albedo and world-space normal of the first diffuse or glossy\n"
            "                     surface seen and the camera distance of the first hit, each the mean over\n"
            "                     the pixel's samples (the buffers a denoiser such as Intel Open Image Denoise\n"
            "                     takes), and the samples each pixel took (fewer under --noise-threshold).\n"
            "                     An .exr output holds them as channels albedo.R/G/B, normal.X/Y/Z, Z and\n"
            "                     samples; a .pfm output NAME.pfm is joined by NAME.albedo.pfm,\n"
            "                     NAME.normal.pfm, NAME.depth.pfm and NAME.samples.pfm. Other formats: a\n"
            "                     usage error\n"
            "      --preview      show the image in a window (SDL2) as it converges, in the output's 8-bit\n"
            "                     encoding; the title shows the progress and the samples per pixel done.\n"
            "                     Esc, Q or closing the window stops the render as Ctrl-C does (the\n"
            "                     partial image is written, exit 130). A finished image is written at once\n"
            "                     and the window stays open until it is closed or Esc/Q is pressed. With no\n"
            "                     display (DISPLAY and WAYLAND_DISPLAY unset), or in a glint built without\n"
            "                     SDL2, it says so and renders without a window\n"
            "      --checkpoint FILE  keep the render's state in FILE: every pixel's samples so far, written\n"
            "                     after each sample pass and when the render ends (Ctrl-C, time limit or done)\n"
            "      --resume FILE  continue the render kept in FILE (and keep checkpointing to it, unless\n"
            "                     --checkpoint names another file): the image is exactly that of an\n"
            "                     uninterrupted render. --spp may grow; the scene's files and every other\n"
            "                     setting must be those of the checkpoint, or it is refused (status 2)\n"
            "      --trace FILE   write a timeline of the threads' work to FILE (Chrome trace-event JSON, for\n"
            "                     https://ui.perfetto.dev or chrome://tracing): scene loading, BVH build, every\n"
            "                     tile pass on every worker, sample passes, waits, checkpoint and image writes.\n"
            "                     Written after the image; the image is the same with or without it\n"
            "  -q, --quiet        no progress bar, statistics line or warnings; errors are still printed\n"
            "  -h, --help         print this help and exit\n"
            "  -V, --version      print the version and exit\n");
    fprintf(f,
            "\n"
            "Short options combine (-qo out.png). Unless --quiet, a progress bar (percentage, elapsed time,\n"
            "ETA) is drawn on stderr when stderr is a terminal, and at the end, terminal or not, one\n"
            "statistics line: wall time, samples/s, rays/s, threads, BVH size, build time and the image.\n"
            "\n"
            "%s"
            "\n"
            "Samples that come out NaN or infinite are dropped, with a warning on stderr (even with\n"
            "--quiet); when more than 1 %% of them were dropped the image is written and the exit status is 1.\n"
            "\n"
            "Scene files (and standard input), meshes and images have size limits, and what renders must lie\n"
            "within [-1e9, 1e9] on every axis: docs/scene-format.md, section Errors, lists them.\n"
            "\n"
            "exit status: 0 success; 1 render, I/O or out-of-memory failure (a read-only output too), or\n"
            "             more than 1 %% of samples dropped; 2 usage or scene error (an output that is one of\n"
            "             the scene's files too); 128 + the signal when stopped by one: 130 SIGINT,\n"
            "             143 SIGTERM, 129 SIGHUP; 130 too when the --preview window stopped it\n"
            "%s",
            prog->stopping, prog->notes);
}

static void usage_hint(const cli_program *prog) {
    if (!prog->silent) fprintf(stderr, "Try '%s --help' for more information.\n", prog->name);
}

// Strict decimal integer: optional sign, digits only, no spaces, in [spec->min, spec->max].
static bool parse_integer(const cli_program *prog, const option_spec *spec, const char *text, long long *out) {
    const char *p = text;
    if (*p == '+' || *p == '-') p++;
    bool digits = *p >= '0' && *p <= '9';
    for (; *p >= '0' && *p <= '9'; p++) {}
    if (!digits || *p != '\0') {
        say(prog, "--%s: '%s' is not an integer, expected an integer in [%lld, %lld]\n", spec->long_name, text,
            spec->min, spec->max);
        return false;
    }
    errno = 0;
    long long v = strtoll(text, NULL, 10);
    if (errno == ERANGE || v < spec->min || v > spec->max) {
        say(prog, "--%s: %s is out of range, expected an integer in [%lld, %lld]\n", spec->long_name, text,
            spec->min, spec->max);
        return false;
    }
    *out = v;
    return true;
}

// "X0,Y0,X1,Y1": four decimal integers, digits only, each saturated at INT_MAX (whether they lie inside the
// image is the library's check, once the image size is known).
static bool parse_region(const char *text, int region[4]) {
    const char *p = text;
    for (int i = 0; i < 4; i++) {
        if (i > 0 && *p++ != ',') return false;
        if (*p < '0' || *p > '9') return false;
        long long v = 0;
        for (; *p >= '0' && *p <= '9'; p++) v = v >= INT_MAX ? INT_MAX : v * 10 + (*p - '0');
        region[i] = v > INT_MAX ? INT_MAX : (int)v;
    }
    return *p == '\0';
}

// "albedo,normal,depth,samples" (any of them, any order, repeats allowed) as glint_aov bits; 0 for a bad list, with the
// message printed.
static unsigned parse_aovs(const char *text) {
    static const struct { const char *name; glint_aov bit; } known[] = {
        {"albedo", GLINT_AOV_ALBEDO}, {"normal", GLINT_AOV_NORMAL}, {"depth", GLINT_AOV_DEPTH},
        {"samples", GLINT_AOV_SAMPLES}};
    unsigned mask = 0;
    const char *p = text;
    for (;;) {
        size_t n = strcspn(p, ",");
        unsigned bit = 0;
        for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
            if (n == strlen(known[i].name) && strncmp(p, known[i].name, n) == 0) bit = (unsigned)known[i].bit;
        if (!bit) {
            fprintf(stderr, "glint: --aov: unknown AOV '%.*s' in '%s', expected a comma-separated list of albedo, "
                            "normal, depth and samples\n", (int)n, p, text);
            return 0;
        }
        mask |= bit;
        if (p[n] == '\0') return mask;
        p += n + 1;
    }
}

// The default image name: the scene file's base name with its extension replaced by .png.
static void set_default_output(cli_options *o) {
    const char *base = strrchr(o->scene_path, '/');
    base = base ? base + 1 : o->scene_path;
    const char *dot = strrchr(base, '.');
    size_t stem = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    if (strcmp(o->scene_path, "-") == 0 || stem == 0 || stem > sizeof o->default_output - 5) {
        snprintf(o->default_output, sizeof o->default_output, "out.png");
    } else {
        snprintf(o->default_output, sizeof o->default_output, "%.*s.png", (int)stem, base);
    }
    o->output = o->default_output;
}

// Whether the output path names a PPM (the only format --ascii-ppm applies to).
static bool is_ppm_path(const char *path) {
    size_t n = strlen(path);
    return strcmp(path, "-") == 0 || (n > 4 && strcasecmp(path + n - 4, ".ppm") == 0);
}

// Applies one option with its value (NULL for flags); returns CLI_RUN to go on.
static cli_action apply_option(const cli_program *prog, const option_spec *spec, const char *value, cli_options *o) {
    long long v = 0;
    if (spec->min <= spec->max && !parse_integer(prog, spec, value, &v)) return CLI_EXIT_USAGE;
    switch (spec->id) {
    case OPT_OUTPUT:
        if (value[0] == '\0') {
            say(prog, "--output: empty file name, expected an image file name or -\n");
            return CLI_EXIT_USAGE;
        }
        o->output = value;
        break;
    case OPT_ASCII_PPM: o->ascii_ppm = true; break;
    case OPT_HALF: o->half = true; break;
    case OPT_WIDTH: o->overrides.width = (long)v; break;
    case OPT_HEIGHT: o->overrides.height = (long)v; break;
    case OPT_SPP: o->overrides.spp = (long)v; break;
    case OPT_DEPTH: o->overrides.max_depth = (long)v; break;
    case OPT_SEED: o->overrides.seed = v; break;
    case OPT_THREADS: o->threads = (int)v; break;
    case OPT_TIME_LIMIT: o->time_limit = (long)v; break;
    case OPT_ACCEL:
        // Checked by glint_scene_override, with the names the library knows (exit 2, the same message).
        o->overrides.accel = value;
        break;
    case OPT_SAMPLER: o->overrides.sampler = value; break; // checked by glint_scene_override, as --accel
    case OPT_NOISE_THRESHOLD: {
        // A plain decimal number (no blanks, signs, hex, inf or nan), in the scene's range.
        char *end = NULL;
        errno = 0;
        bool plain = (value[0] >= '0' && value[0] <= '9') || value[0] == '.';
        double t = plain ? strtod(value, &end) : 0.0;
        if (!plain || end == value || *end != '\0' || strpbrk(value, "xXnN")) {
            say(prog, "--noise-threshold: '%s' is not a number, expected a number in [0, 1000]\n", value);
            return CLI_EXIT_USAGE;
        }
        if (errno || !(t <= 1000.0)) {
            say(prog, "--noise-threshold: %s is out of range, expected a number in [0, 1000]\n", value);
            return CLI_EXIT_USAGE;
        }
        o->overrides.noise_threshold = t;
        break;
    }
    case OPT_OUTPUT_ENCODING:
        o->overrides.output_encoding = value;
        break;
    case OPT_REGION:
        if (!parse_region(value, o->region)) {
            say(prog, "--region: '%s' is not X0,Y0,X1,Y1, expected four non-negative integers separated by "
                      "commas\n", value);
            return CLI_EXIT_USAGE;
        }
        if (o->region[0] >= o->region[2] || o->region[1] >= o->region[3]) {
            say(prog, "--region: %s is empty, expected X0 < X1 and Y0 < Y1\n", value);
            return CLI_EXIT_USAGE;
        }
        break;
    case OPT_AOV:
        o->aovs = parse_aovs(value);
        if (!o->aovs) return CLI_EXIT_USAGE;
        break;
    case OPT_PREVIEW: o->preview = true; break;
    case OPT_CHECKPOINT:
    case OPT_RESUME:
        if (value[0] == '\0') {
            fprintf(stderr, "glint: --%s: empty file name, expected a checkpoint file name\n", spec->long_name);
            return CLI_EXIT_USAGE;
        }
        if (spec->id == OPT_CHECKPOINT) o->checkpoint = value;
        else o->resume = value;
        break;
    case OPT_TRACE:
        if (value[0] == '\0' || strcmp(value, "-") == 0) {
            say(prog, "--trace: '%s' is not a file name, expected the JSON file to write the trace to\n", value);
            return CLI_EXIT_USAGE;
        }
        o->trace = value;
        break;
    case OPT_QUIET: o->quiet = true; break;
    case OPT_HELP: print_usage(prog, stdout); return CLI_EXIT_OK;
    case OPT_VERSION:
        if (!prog->silent) printf("%s %s\n", prog->name, glint_version());
        return CLI_EXIT_OK;
    }
    return CLI_RUN;
}

static const option_spec *find_short(int c) {
    for (int i = 0; i < OPTION_COUNT; i++)
        if (OPTIONS[i].short_name == c) return &OPTIONS[i];
    return NULL;
}

// getopt_long's value for an option: its short letter, or 256 + its index in OPTIONS (no letter is that large).
static int option_value(int i) { return OPTIONS[i].short_name ? OPTIONS[i].short_name : 256 + i; }

static const option_spec *spec_of_value(int v) { return v >= 256 ? &OPTIONS[v - 256] : find_short(v); }

// getopt_long does the GNU syntax (bundled flags "-qo x.png", "-ox.png", "--name=value", "--", options after
// the scene); its messages are silenced (opterr = 0) so that glint's own, unchanged, are printed instead.
cli_action cli_parse(const cli_program *prog, int argc, char **argv, cli_options *o) {
    memset(o, 0, sizeof *o);
    glint_overrides_init(&o->overrides);
    struct option longopts[OPTION_COUNT + 1];
    char shortopts[2 * OPTION_COUNT + 2] = ":"; // ':' first: a missing value returns ':', not '?'
    size_t n = 1;
    for (int i = 0; i < OPTION_COUNT; i++) {
        longopts[i] = (struct option){OPTIONS[i].long_name, OPTIONS[i].takes_value ? required_argument : no_argument,
                                      NULL, option_value(i)};
        if (!OPTIONS[i].short_name) continue;
        shortopts[n++] = OPTIONS[i].short_name;
        if (OPTIONS[i].takes_value) shortopts[n++] = ':';
    }
    shortopts[n] = '\0';
    longopts[OPTION_COUNT] = (struct option){NULL, 0, NULL, 0};
    opterr = 0;
    optind = 1;
    for (int c; (c = getopt_long(argc, argv, shortopts, longopts, NULL)) != -1;) {
        const char *typed = argv[optind - 1]; // the argument that held the option
        const option_spec *spec = c == '?' || c == ':' ? (optopt ? spec_of_value(optopt) : NULL) : spec_of_value(c);
        if (c == '?' && spec) { // "--quiet=yes": only a long option given a value makes a known option fail
            say(prog, "option '--%s' takes no value\n", spec->long_name);
        } else if (c == '?' && optopt && !spec) {
            say(prog, "unknown option '-%c'\n", optopt);
        } else if (c == '?') { // an unknown or ambiguous long option
            say(prog, "unknown option '%s'\n", typed);
        } else if (c == ':') {
            if (strncmp(typed, "--", 2) == 0) say(prog, "option '%s' needs a value\n", typed);
            else say(prog, "option '-%c' needs a value\n", optopt);
        } else {
            cli_action a = apply_option(prog, spec, optarg, o);
            if (a != CLI_RUN) return a;
            continue;
        }
        usage_hint(prog);
        return CLI_EXIT_USAGE;
    }
    for (int i = optind; i < argc; i++) {
        if (o->scene_path) {
            say(prog, "unexpected argument '%s': only one scene file can be given\n", argv[i]);
            usage_hint(prog);
            return CLI_EXIT_USAGE;
        }
        o->scene_path = argv[i];
    }
    if (!o->scene_path) {
        say(prog, "no scene file given\n");
        usage_hint(prog);
        return CLI_EXIT_USAGE;
    }
    if (!o->output) set_default_output(o);
    if (o->resume && !o->checkpoint) o->checkpoint = o->resume; // a resumed render stays resumable
    if (o->ascii_ppm && !is_ppm_path(o->output)) {
        say(prog, "--ascii-ppm: the output '%s' is not a .ppm file (or -)\n", o->output);
        return CLI_EXIT_USAGE;
    }
    size_t out_len = strlen(o->output);
    if (o->half && !(out_len > 4 && strcasecmp(o->output + out_len - 4, ".exr") == 0)) {
        say(prog, "--half: the output '%s' is not an .exr file\n", o->output);
        return CLI_EXIT_USAGE;
    }
    bool exr = out_len > 4 && strcasecmp(o->output + out_len - 4, ".exr") == 0;
    bool pfm = out_len > 4 && strcasecmp(o->output + out_len - 4, ".pfm") == 0;
    if (o->aovs && !exr && !pfm) {
        fprintf(stderr, "glint: --aov: the output '%s' is not an .exr or .pfm file, expected an OpenEXR file (AOVs "
                        "as channels) or a PFM (AOVs in files beside it)\n", o->output);
        return CLI_EXIT_USAGE;
    }
    // A PFM holds one image: each AOV goes to a file of its own, NAME.albedo.pfm beside NAME.pfm.
    static const char *const aov_names[CLI_AOV_COUNT] = {"albedo", "normal", "depth", "samples"};
    for (int i = 0; pfm && i < CLI_AOV_COUNT; i++) {
        if (!(o->aovs & (1u << i))) continue;
        int len = snprintf(o->aov_output[i], sizeof o->aov_output[i], "%.*s.%s%s", (int)(out_len - 4), o->output,
                           aov_names[i], o->output + out_len - 4);
        if (len < 0 || (size_t)len >= sizeof o->aov_output[i]) {
            fprintf(stderr, "glint: --aov: the output name '%s' is too long for the AOV files beside it\n", o->output);
            return CLI_EXIT_USAGE;
        }
    }
    return CLI_RUN;
}

int cli_merge(int argc, char **argv) {
    const cli_program *prog = &CLI_GLINT;
    if (argc < 4) {
        say(prog, "merge: expected OUT and at least one PART: glint merge OUT PART...\n");
        usage_hint(prog);
        return CLI_EXIT_USAGE;
    }
    glint_error err;
    glint_status st = glint_merge(argv[2], (const char *const *)(argv + 3), (size_t)(argc - 3), &err);
    if (st == GLINT_OK) return 0;
    say(prog, "%s\n", err.message);
    return st == GLINT_ERR_INPUT ? 2 : 1;
}
