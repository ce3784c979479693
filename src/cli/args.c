// args.c — glint's command line: a table of options, strict integer values, --help and --version.
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

typedef enum option_id {
    OPT_OUTPUT, OPT_ASCII_PPM, OPT_WIDTH, OPT_HEIGHT, OPT_SPP, OPT_DEPTH, OPT_SEED, OPT_THREADS, OPT_ACCEL,
    OPT_QUIET, OPT_HELP, OPT_VERSION
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
    {"width", 0, true, OPT_WIDTH, 1, 16384},
    {"height", 0, true, OPT_HEIGHT, 1, 16384},
    {"spp", 0, true, OPT_SPP, 1, 1000000},
    {"depth", 0, true, OPT_DEPTH, 0, 10000},
    {"seed", 0, true, OPT_SEED, 0, 9007199254740992LL}, // 2^53: every seed a JSON number holds exactly
    {"threads", 0, true, OPT_THREADS, 1, 256},
    {"accel", 0, true, OPT_ACCEL, 1, 0},
    {"quiet", 'q', false, OPT_QUIET, 1, 0},
    {"help", 'h', false, OPT_HELP, 1, 0},
    {"version", 'V', false, OPT_VERSION, 1, 0},
};
enum { OPTION_COUNT = sizeof OPTIONS / sizeof OPTIONS[0] };

static void print_usage(FILE *f) {
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    fprintf(f,
            "usage: glint [options] SCENE\n"
            "\n"
            "Renders the JSON scene file SCENE (- reads it from standard input) and writes the image.\n"
            "Options override the scene file's \"render\" settings.\n"
            "\n"
            "options:\n"
            "  -o, --output FILE  the image to write; its extension chooses the format:\n"
            "                     .png (8-bit RGB), .ppm (binary P6), .pfm (linear float RGB);\n"
            "                     - writes PPM to standard output. Default: the scene's file name with\n"
            "                     .png, in the current directory (scenes/paper.json -> paper.png;\n"
            "                     out.png when the scene comes from standard input)\n"
            "      --ascii-ppm    write PPM as ASCII P3, as the seeds print it, instead of binary P6\n"
            "      --width N      image width in pixels, 1..16384\n"
            "      --height N     image height in pixels, 1..16384\n"
            "      --spp N        samples per pixel, 1..1000000\n"
            "      --depth N      maximum recursion (Whitted) or bounce (path) depth, 0..10000\n"
            "      --seed N       random seed, 0..9007199254740992 (2^53)\n"
            "      --threads N    worker threads, 1..256; default: all online CPUs (%ld here);\n"
            "                     1 renders sequentially. The image is the same for every N\n"
            "      --accel KIND   acceleration structure: bvh, bvh2 or none (brute force)\n"
            "  -q, --quiet        no progress bar and no statistics line; errors are still printed\n"
            "  -h, --help         print this help and exit\n"
            "  -V, --version      print the version and exit\n"
            "\n"
            "On a terminal, a progress bar (percentage, elapsed time, ETA) is drawn on stderr, and at the\n"
            "end one statistics line: wall time, samples/s, rays/s, threads, BVH size and build time.\n"
            "\n"
            "Ctrl-C (SIGINT) or SIGTERM stops the render within a second and writes the image rendered so\n"
            "far (each pixel the mean of its completed samples; nothing if no sample was completed);\n"
            "a second Ctrl-C aborts at once.\n"
            "\n"
            "Samples that come out NaN or infinite are dropped, with a warning on stderr (even with\n"
            "--quiet); when more than 1 %% of them were dropped the image is written and the exit status is 1.\n"
            "\n"
            "exit status: 0 success; 1 render or I/O failure, or more than 1 %% of samples dropped;\n"
            "             2 usage or scene error;\n"
            "             130 stopped by SIGINT, 143 by SIGTERM (partial image written)\n",
            cpus > 0 ? cpus : 1);
}

static void usage_hint(void) { fputs("Try 'glint --help' for more information.\n", stderr); }

// Strict decimal integer: optional sign, digits only, no spaces, in [spec->min, spec->max].
static bool parse_integer(const option_spec *spec, const char *text, long long *out) {
    const char *p = text;
    if (*p == '+' || *p == '-') p++;
    bool digits = *p >= '0' && *p <= '9';
    for (; *p >= '0' && *p <= '9'; p++) {}
    if (!digits || *p != '\0') {
        fprintf(stderr, "glint: --%s: '%s' is not an integer, expected an integer in [%lld, %lld]\n",
                spec->long_name, text, spec->min, spec->max);
        return false;
    }
    errno = 0;
    long long v = strtoll(text, NULL, 10);
    if (errno == ERANGE || v < spec->min || v > spec->max) {
        fprintf(stderr, "glint: --%s: %s is out of range, expected an integer in [%lld, %lld]\n", spec->long_name,
                text, spec->min, spec->max);
        return false;
    }
    *out = v;
    return true;
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
static cli_action apply_option(const option_spec *spec, const char *value, cli_options *o) {
    long long v = 0;
    if (spec->min <= spec->max && !parse_integer(spec, value, &v)) return CLI_EXIT_USAGE;
    switch (spec->id) {
    case OPT_OUTPUT:
        if (value[0] == '\0') {
            fprintf(stderr, "glint: --output: empty file name, expected an image file name or -\n");
            return CLI_EXIT_USAGE;
        }
        o->output = value;
        break;
    case OPT_ASCII_PPM: o->ascii_ppm = true; break;
    case OPT_WIDTH: o->overrides.width = (long)v; break;
    case OPT_HEIGHT: o->overrides.height = (long)v; break;
    case OPT_SPP: o->overrides.spp = (long)v; break;
    case OPT_DEPTH: o->overrides.max_depth = (long)v; break;
    case OPT_SEED: o->overrides.seed = v; break;
    case OPT_THREADS: o->threads = (int)v; break;
    case OPT_ACCEL:
        if (strcmp(value, "bvh") != 0 && strcmp(value, "bvh2") != 0 && strcmp(value, "none") != 0) {
            fprintf(stderr, "glint: --accel: unknown structure '%s', expected bvh, bvh2 or none\n", value);
            return CLI_EXIT_USAGE;
        }
        o->overrides.accel = value;
        break;
    case OPT_QUIET: o->quiet = true; break;
    case OPT_HELP: print_usage(stdout); return CLI_EXIT_OK;
    case OPT_VERSION: printf("glint %s\n", glint_version()); return CLI_EXIT_OK;
    }
    return CLI_RUN;
}

static const option_spec *find_long(const char *name, size_t len) {
    for (int i = 0; i < OPTION_COUNT; i++)
        if (strlen(OPTIONS[i].long_name) == len && strncmp(OPTIONS[i].long_name, name, len) == 0) return &OPTIONS[i];
    return NULL;
}

static const option_spec *find_short(char c) {
    for (int i = 0; i < OPTION_COUNT; i++)
        if (OPTIONS[i].short_name == c) return &OPTIONS[i];
    return NULL;
}

cli_action cli_parse(int argc, char **argv, cli_options *o) {
    memset(o, 0, sizeof *o);
    glint_overrides_init(&o->overrides);
    bool options_done = false;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (options_done || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (o->scene_path) {
                fprintf(stderr, "glint: unexpected argument '%s': only one scene file can be given\n", arg);
                usage_hint();
                return CLI_EXIT_USAGE;
            }
            o->scene_path = arg;
            continue;
        }
        if (strcmp(arg, "--") == 0) { options_done = true; continue; }
        const option_spec *spec;
        const char *value = NULL;
        if (arg[1] == '-') {
            // --name or --name=value
            const char *eq = strchr(arg + 2, '=');
            size_t len = eq ? (size_t)(eq - (arg + 2)) : strlen(arg + 2);
            spec = find_long(arg + 2, len);
            if (spec && eq) {
                if (!spec->takes_value) {
                    fprintf(stderr, "glint: option '--%s' takes no value\n", spec->long_name);
                    usage_hint();
                    return CLI_EXIT_USAGE;
                }
                value = eq + 1;
            }
        } else {
            // -x, or -oVALUE for an option with a value
            spec = find_short(arg[1]);
            if (spec && arg[2] != '\0') {
                if (!spec->takes_value) spec = NULL; // "-qx": unknown, no bundling
                else value = arg + 2;
            }
        }
        if (!spec) {
            fprintf(stderr, "glint: unknown option '%s'\n", arg);
            usage_hint();
            return CLI_EXIT_USAGE;
        }
        if (spec->takes_value && !value) {
            if (i + 1 >= argc) {
                fprintf(stderr, "glint: option '%s' needs a value\n", arg);
                usage_hint();
                return CLI_EXIT_USAGE;
            }
            value = argv[++i];
        }
        cli_action a = apply_option(spec, value, o);
        if (a != CLI_RUN) return a;
    }
    if (!o->scene_path) {
        fprintf(stderr, "glint: no scene file given\n");
        usage_hint();
        return CLI_EXIT_USAGE;
    }
    if (!o->output) set_default_output(o);
    if (o->ascii_ppm && !is_ppm_path(o->output)) {
        fprintf(stderr, "glint: --ascii-ppm: the output '%s' is not a .ppm file (or -)\n", o->output);
        return CLI_EXIT_USAGE;
    }
    return CLI_RUN;
}
