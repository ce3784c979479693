// test_merge.c — float merges: a scene rendered whole and in random partitions into 2 to 6 regions (a fixed seed),
// each region written as OpenEXR (float and half) and as PFM with its AOV PFMs; glint_merge of the parts gives
// exactly the full render: every channel of the EXR (AOVs included) bit for bit against the render's own floats,
// the half EXR's values and channel types as the full half render's, and the PFM, AOV PFM and HDR files byte for
// byte. Region PFMs carry their region file, whose hash ties it to the PFM's bytes.
#include "check.h"
#include "glint.h"
#include "io/exr_read.h"
#include "io/pfm_region.h"
#include "test_util.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { WIDTH = 64, HEIGHT = 48, MAX_PARTS = 6, TRIALS = 6, MAX_CHANNELS = 16 };

// The channels of an OpenEXR file as glint's reader decodes them: one float array per channel.
typedef struct exr_planes {
    int count, width, height, display[4], data[4];
    char names[MAX_CHANNELS][32];
    exr_channel_type types[MAX_CHANNELS];
    float *values[MAX_CHANNELS];
} exr_planes;

static void exr_planes_free(exr_planes *e) {
    for (int c = 0; c < e->count; c++) free(e->values[c]);
    memset(e, 0, sizeof *e);
}

static bool read_exr(const char *path, exr_planes *out) {
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    exr_part *p = NULL;
    exr_part_info info;
    glint_error err;
    bool ok = exr_part_open(f, path, (size_t)1 << 24, &p, &info, &err) == GLINT_OK;
    ok = ok && info.channel_count <= MAX_CHANNELS;
    exr_channel_target targets[MAX_CHANNELS];
    if (ok) {
        out->count = info.channel_count;
        out->width = info.data[2] - info.data[0];
        out->height = info.data[3] - info.data[1];
        memcpy(out->display, info.display, sizeof out->display);
        memcpy(out->data, info.data, sizeof out->data);
        for (int c = 0; c < out->count; c++) {
            snprintf(out->names[c], sizeof out->names[c], "%s", info.channels[c].name);
            out->types[c] = info.channels[c].type;
            out->values[c] = calloc((size_t)out->width * (size_t)out->height, sizeof(float));
            ok = ok && out->values[c];
            targets[c] = (exr_channel_target){out->values[c], 1, (size_t)out->width};
        }
    }
    if (ok) ok = exr_part_decode(p, targets, &err) == GLINT_OK;
    if (!ok) fprintf(stderr, "%s: %s\n", path, p ? err.message : "cannot open");
    exr_part_close(p);
    fclose(f);
    if (!ok) exr_planes_free(out);
    return ok;
}

// The index of channel `name`, -1 when the file has none.
static int channel_index(const exr_planes *e, const char *name) {
    for (int c = 0; c < e->count; c++)
        if (strcmp(e->names[c], name) == 0) return c;
    return -1;
}

// Whether channel `name` of e holds exactly (bit for bit) component `component` of the image plane `plane`
// (`stride` floats a pixel).
static bool channel_equals(const exr_planes *e, const char *name, const float *plane, int stride, int component) {
    int c = channel_index(e, name);
    if (c < 0 || !plane) return false;
    for (size_t i = 0; i < (size_t)e->width * (size_t)e->height; i++)
        if (memcmp(&e->values[c][i], &plane[i * (size_t)stride + (size_t)component], sizeof(float)) != 0) return false;
    return true;
}

// Whether two EXR files hold the same channels, of the same types, windows and values bit for bit.
static bool exr_same(const char *a, const char *b) {
    exr_planes x, y;
    if (!read_exr(a, &x)) return false;
    if (!read_exr(b, &y)) {
        exr_planes_free(&x);
        return false;
    }
    bool same = x.count == y.count && memcmp(x.display, y.display, sizeof x.display) == 0 &&
                memcmp(x.data, y.data, sizeof x.data) == 0;
    for (int c = 0; same && c < x.count; c++)
        same = strcmp(x.names[c], y.names[c]) == 0 && x.types[c] == y.types[c] &&
               memcmp(x.values[c], y.values[c], (size_t)x.width * (size_t)x.height * sizeof(float)) == 0;
    exr_planes_free(&x);
    exr_planes_free(&y);
    return same;
}

// Whether two files hold the same bytes.
static bool files_same(const char *a, const char *b) {
    FILE *f = fopen(a, "rb"), *g = fopen(b, "rb");
    bool same = f && g;
    for (int c = 0, d = 0; same && c != EOF; same = c == d) {
        c = fgetc(f);
        d = fgetc(g);
    }
    if (f) fclose(f);
    if (g) fclose(g);
    return same;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15u; // a fixed seed: the partitions are the same on every run

static uint32_t rng_below(uint32_t n) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state % n);
}

// A random partition of the image into `count` rectangles: a random rectangle wide or tall enough is cut across
// at a random place, until there are count of them.
static void partition(int count, int regions[][4]) {
    regions[0][0] = regions[0][1] = 0;
    regions[0][2] = WIDTH;
    regions[0][3] = HEIGHT;
    for (int n = 1; n < count;) {
        int *r = regions[rng_below((uint32_t)n)];
        int axis = (int)rng_below(2), lo = r[axis], hi = r[axis + 2];
        if (hi - lo < 2) continue;
        int cut = lo + 1 + (int)rng_below((uint32_t)(hi - lo - 1));
        int *next = regions[n++];
        memcpy(next, r, 4 * sizeof *r);
        r[axis + 2] = cut;
        next[axis] = cut;
    }
}

static glint_image *render(glint_scene *scene, const int region[4]) {
    glint_render_options opt;
    memset(&opt, 0, sizeof opt);
    opt.threads = 2;
    opt.aovs = GLINT_AOV_ALL;
    if (region) memcpy(opt.region, region, sizeof opt.region);
    glint_image *img = NULL;
    glint_error err;
    if (glint_render(scene, &opt, NULL, NULL, &img, NULL, &err) != GLINT_OK) {
        fprintf(stderr, "render: %s\n", err.message);
        glint_image_free(img);
        return NULL;
    }
    return img;
}

static const char *const AOV_NAMES[3] = {"albedo", "normal", "depth"};

// Writes img as NAME.exr, NAME-half.exr, NAME.pfm with NAME.albedo.pfm, NAME.normal.pfm and NAME.depth.pfm, and
// (whole images alone) NAME.hdr.
static bool write_all(const glint_image *img, const char *name, bool hdr) {
    glint_error err;
    char path[64];
    bool ok = true;
    snprintf(path, sizeof path, "%s.exr", name);
    ok = ok && glint_image_write(img, tmp_path(path), GLINT_FORMAT_EXR, &err) == GLINT_OK;
    snprintf(path, sizeof path, "%s-half.exr", name);
    ok = ok && glint_image_write(img, tmp_path(path), GLINT_FORMAT_EXR_HALF, &err) == GLINT_OK;
    snprintf(path, sizeof path, "%s.pfm", name);
    ok = ok && glint_image_write(img, tmp_path(path), GLINT_FORMAT_PFM, &err) == GLINT_OK;
    for (int a = 0; a < 3; a++) {
        snprintf(path, sizeof path, "%s.%s.pfm", name, AOV_NAMES[a]);
        ok = ok && glint_image_write_aov(img, (glint_aov)(1u << a), tmp_path(path), &err) == GLINT_OK;
    }
    snprintf(path, sizeof path, "%s.hdr", name);
    if (hdr) ok = ok && glint_image_write(img, tmp_path(path), GLINT_FORMAT_HDR, &err) == GLINT_OK;
    if (!ok) fprintf(stderr, "write %s: %s\n", name, err.message);
    return ok;
}

// Merges the parts part-K<suffix> (K in order[]) into out; true when glint_merge succeeds.
static bool merge(const char *out, int count, const int order[], const char *suffix) {
    static char paths[MAX_PARTS][1024];
    const char *parts[MAX_PARTS];
    for (int k = 0; k < count; k++) {
        char name[64];
        snprintf(name, sizeof name, "part-%d%s", order[k], suffix);
        snprintf(paths[k], sizeof paths[k], "%s", tmp_path(name));
        parts[k] = paths[k];
    }
    glint_error err;
    glint_status st = glint_merge(tmp_path(out), parts, (size_t)count, &err);
    if (st != GLINT_OK) fprintf(stderr, "merge %s: %s\n", out, err.message);
    return st == GLINT_OK;
}

// The merged EXR holds every channel of the render, each exactly the render's floats.
static void check_merged_exr(const char *path, const glint_image *full) {
    exr_planes e;
    CHECK(read_exr(path, &e));
    CHECK(e.count == 11);
    CHECK(e.width == WIDTH && e.height == HEIGHT && e.data[0] == 0 && e.display[2] == WIDTH);
    int w, h, albedo_n, normal_n, depth_n, samples_n;
    const float *rgb;
    glint_image_info(full, &w, &h, &rgb);
    const float *albedo = glint_image_aov(full, GLINT_AOV_ALBEDO, &albedo_n);
    const float *normal = glint_image_aov(full, GLINT_AOV_NORMAL, &normal_n);
    const float *depth = glint_image_aov(full, GLINT_AOV_DEPTH, &depth_n);
    const float *samples = glint_image_aov(full, GLINT_AOV_SAMPLES, &samples_n);
    static const char *const colour[3] = {"R", "G", "B"}, *const albedo_names[3] = {"albedo.R", "albedo.G", "albedo.B"},
                             *const normal_names[3] = {"normal.X", "normal.Y", "normal.Z"};
    for (int c = 0; c < 3; c++) {
        CHECK(channel_equals(&e, colour[c], rgb, 3, c));
        CHECK(channel_equals(&e, albedo_names[c], albedo, albedo_n, c));
        CHECK(channel_equals(&e, normal_names[c], normal, normal_n, c));
    }
    CHECK(channel_equals(&e, "Z", depth, depth_n, 0));
    CHECK(channel_equals(&e, "samples", samples, samples_n, 0));
    exr_planes_free(&e);
}

static void test_random_partitions(void) {
    char scene_path[4096];
    snprintf(scene_path, sizeof scene_path, "%s/scenes/cornell-box.json", GLINT_SOURCE_DIR);
    glint_scene *scene = NULL;
    glint_error err;
    CHECK(glint_scene_load(scene_path, &scene, &err) == GLINT_OK);
    if (!scene) return;
    glint_overrides o;
    glint_overrides_init(&o);
    o.width = WIDTH;
    o.height = HEIGHT;
    o.spp = 2;
    CHECK(glint_scene_override(scene, &o, &err) == GLINT_OK);
    glint_image *full = render(scene, NULL);
    CHECK(full != NULL);
    if (!full) {
        glint_scene_free(scene);
        return;
    }
    CHECK(write_all(full, "full", true));
    // Every comparison is of bits: +infinity (depth where nothing was hit) and -0 must come back as they were.
    for (int trial = 0; trial < TRIALS; trial++) {
        int count = 2 + (int)rng_below(MAX_PARTS - 1), regions[MAX_PARTS][4], order[MAX_PARTS];
        partition(count, regions);
        for (int k = 0; k < count; k++) {
            glint_image *part = render(scene, regions[k]);
            CHECK(part != NULL);
            char name[32];
            snprintf(name, sizeof name, "part-%d", k);
            if (part) CHECK(write_all(part, name, false));
            glint_image_free(part);
            order[k] = k;
        }
        // The parts in a random order: a merge places each by its own region.
        for (int k = count - 1; k > 0; k--) {
            int j = (int)rng_below((uint32_t)k + 1u), t = order[k];
            order[k] = order[j];
            order[j] = t;
        }
        CHECK(merge("merged.exr", count, order, ".exr"));
        check_merged_exr(tmp_path("merged.exr"), full);
        CHECK(exr_same(tmp_path("merged.exr"), tmp_path("full.exr")));
        CHECK(files_same(tmp_path("merged.exr"), tmp_path("full.exr")));
        // Half parts merge to a half file: the full half render's values and types, channel for channel.
        CHECK(merge("merged-half.exr", count, order, "-half.exr"));
        CHECK(exr_same(tmp_path("merged-half.exr"), tmp_path("full-half.exr")));
        CHECK(merge("merged.pfm", count, order, ".pfm"));
        CHECK(files_same(tmp_path("merged.pfm"), tmp_path("full.pfm")));
        for (int a = 0; a < 3; a++) {
            char suffix[16], out[32], want[32];
            snprintf(suffix, sizeof suffix, ".%s.pfm", AOV_NAMES[a]);
            snprintf(out, sizeof out, "merged%s", suffix);
            snprintf(want, sizeof want, "full%s", suffix);
            CHECK(merge(out, count, order, suffix));
            CHECK(files_same(tmp_path(out), tmp_path(want)));
        }
        // From the exact floats, whatever the parts' format: a PFM and an HDR as the full render's.
        CHECK(merge("from-exr.pfm", count, order, ".exr"));
        CHECK(files_same(tmp_path("from-exr.pfm"), tmp_path("full.pfm")));
        CHECK(merge("merged.hdr", count, order, ".pfm"));
        CHECK(files_same(tmp_path("merged.hdr"), tmp_path("full.hdr")));
        CHECK(!files_same(tmp_path("merged.hdr"), tmp_path("full.pfm"))); // the comparison can fail
        for (int k = 0; k < count; k++) {
            char name[64];
            snprintf(name, sizeof name, "part-%d.pfm.region", k);
            CHECK(access(tmp_path(name), R_OK) == 0);
        }
    }
    // A whole image's PFM has no region file; a region's records its place and its PFM's hash.
    CHECK(access(tmp_path("full.pfm.region"), F_OK) != 0);
    CHECK(access(tmp_path("merged.pfm.region"), F_OK) != 0);
    glint_image_free(full);
    glint_scene_free(scene);
}

// The region file's text and its strict reading.
static void test_region_file_text(void) {
    char text[PFM_REGION_MAX_BYTES], region[64];
    int r[4] = {3, 4, 60, 48};
    int n = pfm_region_text(text, sizeof text, r, 64, 48, UINT64_C(0x0123456789abcdef));
    CHECK(strcmp(text, "glint:region=3,4,60,48,64,48\nfnv1a64=0123456789abcdef\n") == 0);
    uint64_t hash = 0;
    CHECK(pfm_region_split(text, (size_t)n, region, sizeof region, &hash));
    CHECK(strcmp(region, "3,4,60,48,64,48") == 0 && hash == UINT64_C(0x0123456789abcdef));
    CHECK(!pfm_region_split(text, (size_t)n - 1, region, sizeof region, &hash));         // no final newline
    CHECK(!pfm_region_split("glint:region=1\nfnv1a64=0123456789ABCDEF\n", 41, region, sizeof region, &hash));
    CHECK(!pfm_region_split("glint:region=1\nfnv1a64=0123456789abcdef\nx", 41, region, sizeof region, &hash));
    CHECK(!pfm_region_split("glint:region=1", 14, region, sizeof region, &hash));
    pfm_header h;
    char why[160];
    CHECK(pfm_parse_header((const unsigned char *)"PF\n64 48\n-1.0\n", 14, &h, why, sizeof why));
    CHECK(h.width == 64 && h.height == 48 && h.channels == 3 && h.little_endian && h.bytes == 14);
    CHECK(pfm_parse_header((const unsigned char *)"Pf 2 3 1 ", 9, &h, why, sizeof why));
    CHECK(h.channels == 1 && !h.little_endian && h.bytes == 9);
    CHECK(!pfm_parse_header((const unsigned char *)"PF\n64 48\n-1.0", 13, &h, why, sizeof why)); // no byte after
    CHECK(!pfm_parse_header((const unsigned char *)"PF\n0 48\n-1.0\n", 13, &h, why, sizeof why));
    CHECK(!pfm_parse_header((const unsigned char *)"PF\n64 48\n0\n", 11, &h, why, sizeof why));
    CHECK(!pfm_parse_header((const unsigned char *)"PF\n99999999999 48\n-1\n", 22, &h, why, sizeof why));
    CHECK(!pfm_parse_header((const unsigned char *)"P6\n64 48\n255\n", 13, &h, why, sizeof why));
}

int main(void) {
    if (!tmpdir_make("glint-test-merge")) return 1;
    test_region_file_text();
    test_random_partitions();
    tmpdir_remove();
    return check_summary();
}
