// checkpoint.c — checkpoint files: a fixed header (magic, version, byte order, the render's identity), the
// scene's name, a table of planes, a checksum of all that, the planes' data and a checksum of the data. Numbers
// are in the writing machine's byte order (the header says which), so planes go to and from disk in one piece.
#include "render/checkpoint.h"
#include "core/filepath.h"
#include "core/hash.h"
#include "core/names.h"
#include "io/image_write.h"

#include <errno.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char MAGIC[8] = {'G', 'L', 'I', 'N', 'T', 'C', 'K', 'P'};
static const uint32_t BYTE_ORDER_MARK = 0x01020304u;

enum {
    NAME_MAX_BYTES = 4096, ///< the scene's name kept for messages (longer names are cut)
    PLANE_NAME_BYTES = 16,
    MAX_PLANES = 64,
    HASH_CHUNK = 1 << 16,
};

/// The fixed part at the start of the file, as it lies on disk (no padding: 4- and 8-byte fields, aligned).
typedef struct header {
    char magic[8];
    uint32_t version, byte_order;
    uint64_t scene_hash, seed;
    int32_t width, height, max_depth, integrator, whitted_mode, accel, encoding, light_sampling;
    int32_t region[4];
    int32_t sampler;                  ///< sampler_kind
    float noise_threshold;            ///< adaptive sampling's threshold (0: off)
    int32_t spp, complete;            ///< samples per pixel of the render; samples every pixel has
    uint32_t plane_count, name_bytes; ///< the table of planes and the scene's name follow
} header;
_Static_assert(sizeof(header) == 104, "the checkpoint header has no padding");

/// One entry of the table of planes, as on disk.
typedef struct plane_entry {
    char name[PLANE_NAME_BYTES];
    uint32_t type, components;
} plane_entry;
_Static_assert(sizeof(plane_entry) == 24, "a plane entry has no padding");

// ---- identity ----

glint_status checkpoint_scene_hash(const glint_scene *s, uint64_t *hash, glint_error *err) {
    uint64_t h = hash_u64(HASH_START, s->text_hash);
    unsigned char *buf = malloc(HASH_CHUNK);
    if (!buf) {
        snprintf(err->message, sizeof err->message, "out of memory while hashing the scene's files");
        return GLINT_ERR_RENDER;
    }
    for (size_t i = 0; i < s->input_count; i++) {
        FILE *f = fopen(s->inputs[i].path, "rb");
        if (!f) {
            snprintf(err->message, sizeof err->message, "%s: cannot read it again for the checkpoint: %s",
                     s->inputs[i].path, strerror(errno));
            free(buf);
            return GLINT_ERR_INPUT;
        }
        uint64_t length = 0;
        for (size_t n; (n = fread(buf, 1, HASH_CHUNK, f)) > 0; length += n) h = hash_bytes(h, buf, n);
        bool failed = ferror(f) != 0;
        fclose(f);
        if (failed) {
            snprintf(err->message, sizeof err->message, "%s: cannot read it again for the checkpoint", s->inputs[i].path);
            free(buf);
            return GLINT_ERR_INPUT;
        }
        h = hash_u64(h, length); // so that no file's end can pass for the next one's start
    }
    free(buf);
    *hash = h;
    return GLINT_OK;
}

glint_status checkpoint_identity_of(const glint_scene *s, const int region[4], bool light_sampling,
                                    checkpoint_identity *id, glint_error *err) {
    const render_settings *rs = &s->settings;
    memset(id, 0, sizeof *id);
    id->scene_name = s->path;
    id->seed = rs->seed;
    id->width = rs->width;
    id->height = rs->height;
    id->max_depth = rs->max_depth;
    id->integrator = (int32_t)rs->integrator;
    id->whitted_mode = (int32_t)rs->whitted_mode;
    id->accel = (int32_t)rs->accel;
    id->encoding = (int32_t)rs->transform;
    id->light_sampling = light_sampling ? 1 : 0;
    // The sampler that draws the render's numbers: the Whitted integrators always draw independent ones.
    id->sampler = (int32_t)(rs->integrator == INTEGRATOR_PATH ? rs->sampler : SAMPLER_INDEPENDENT);
    id->noise_threshold = rs->noise_threshold;
    for (int i = 0; i < 4; i++) id->region[i] = region[i];
    return checkpoint_scene_hash(s, &id->scene_hash, err);
}

// ---- sizes ----

static size_t type_size(uint32_t type) { return type == CHECKPOINT_U32 ? 4u : type == CHECKPOINT_F64 ? 8u : 0u; }

static uint64_t region_pixels(const int32_t r[4]) {
    return (uint64_t)(r[2] - r[0]) * (uint64_t)(r[3] - r[1]);
}

// ---- writing ----

typedef struct write_job {
    const checkpoint_identity *id;
    int spp, complete;
    const checkpoint_plane *planes;
    size_t plane_count;
} write_job;

static int put(FILE *f, const void *data, size_t n, uint64_t *h) {
    *h = hash_bytes(*h, data, n);
    errno = 0;
    return fwrite(data, 1, n, f) == n ? 0 : (errno ? errno : EIO);
}

static int write_checkpoint(FILE *f, const void *user, char *why, size_t why_size) {
    (void)why;
    (void)why_size;
    const write_job *job = user;
    const checkpoint_identity *id = job->id;
    size_t name_bytes = strlen(id->scene_name);
    if (name_bytes > NAME_MAX_BYTES) name_bytes = NAME_MAX_BYTES;
    header hd;
    memset(&hd, 0, sizeof hd);
    memcpy(hd.magic, MAGIC, sizeof MAGIC);
    hd.version = CHECKPOINT_VERSION;
    hd.byte_order = BYTE_ORDER_MARK;
    hd.scene_hash = id->scene_hash;
    hd.seed = id->seed;
    hd.width = id->width;
    hd.height = id->height;
    hd.max_depth = id->max_depth;
    hd.integrator = id->integrator;
    hd.whitted_mode = id->whitted_mode;
    hd.accel = id->accel;
    hd.encoding = id->encoding;
    hd.light_sampling = id->light_sampling;
    hd.sampler = id->sampler;
    hd.noise_threshold = id->noise_threshold;
    memcpy(hd.region, id->region, sizeof hd.region);
    hd.spp = job->spp;
    hd.complete = job->complete;
    hd.plane_count = (uint32_t)job->plane_count;
    hd.name_bytes = (uint32_t)name_bytes;
    uint64_t h = HASH_START;
    int rc = put(f, &hd, sizeof hd, &h);
    if (rc == 0) rc = put(f, id->scene_name, name_bytes, &h);
    for (size_t i = 0; rc == 0 && i < job->plane_count; i++) {
        plane_entry e;
        memset(&e, 0, sizeof e);
        snprintf(e.name, sizeof e.name, "%s", job->planes[i].name);
        e.type = (uint32_t)job->planes[i].type;
        e.components = job->planes[i].components;
        rc = put(f, &e, sizeof e, &h);
    }
    uint64_t header_hash = h;
    if (rc == 0) rc = put(f, &header_hash, sizeof header_hash, &h);
    uint64_t pixels = region_pixels(id->region);
    h = HASH_START; // the data's own checksum
    for (size_t i = 0; rc == 0 && i < job->plane_count; i++) {
        const checkpoint_plane *p = &job->planes[i];
        rc = put(f, p->data, (size_t)pixels * p->components * type_size((uint32_t)p->type), &h);
    }
    uint64_t data_hash = h;
    if (rc == 0) rc = put(f, &data_hash, sizeof data_hash, &h);
    return rc;
}

glint_status checkpoint_write(const char *path, const checkpoint_identity *id, int spp, int complete,
                              const checkpoint_plane *planes, size_t plane_count, glint_error *err) {
    write_job job = {id, spp, complete, planes, plane_count};
    return image_write_file(path, write_checkpoint, &job, err);
}

// ---- reading ----

// The name of value v of an enum whose table is `names` ("unknown" for a damaged file's value).
#define NAME_OF(names, v) names_get(names, sizeof names / sizeof names[0], v)

// The first setting in which the file's header and this render differ, described for each ("seed 1" and
// "seed 2"); false when they agree in every one.
static bool first_difference(const header *hd, const checkpoint_identity *id, char *was, char *is, size_t size) {
    if (hd->width != id->width || hd->height != id->height) {
        snprintf(was, size, "size %dx%d", (int)hd->width, (int)hd->height);
        snprintf(is, size, "size %dx%d", (int)id->width, (int)id->height);
    } else if (memcmp(hd->region, id->region, sizeof hd->region) != 0) {
        snprintf(was, size, "region %d,%d,%d,%d", (int)hd->region[0], (int)hd->region[1], (int)hd->region[2],
                 (int)hd->region[3]);
        snprintf(is, size, "region %d,%d,%d,%d", (int)id->region[0], (int)id->region[1], (int)id->region[2],
                 (int)id->region[3]);
    } else if (hd->seed != id->seed) {
        snprintf(was, size, "seed %llu", (unsigned long long)hd->seed);
        snprintf(is, size, "seed %llu", (unsigned long long)id->seed);
    } else if (hd->max_depth != id->max_depth) {
        snprintf(was, size, "depth %d", (int)hd->max_depth);
        snprintf(is, size, "depth %d", (int)id->max_depth);
    } else if (hd->integrator != id->integrator || hd->whitted_mode != id->whitted_mode) {
        snprintf(was, size, "integrator %s (%s)", NAME_OF(integrator_kind_names, hd->integrator),
                 NAME_OF(whitted_mode_names, hd->whitted_mode));
        snprintf(is, size, "integrator %s (%s)", NAME_OF(integrator_kind_names, id->integrator),
                 NAME_OF(whitted_mode_names, id->whitted_mode));
    } else if (hd->accel != id->accel) {
        snprintf(was, size, "accel %s", NAME_OF(accel_kind_names, hd->accel));
        snprintf(is, size, "accel %s", NAME_OF(accel_kind_names, id->accel));
    } else if (hd->encoding != id->encoding) {
        snprintf(was, size, "output encoding %s", NAME_OF(output_transform_names, hd->encoding));
        snprintf(is, size, "output encoding %s", NAME_OF(output_transform_names, id->encoding));
    } else if (hd->light_sampling != id->light_sampling) {
        snprintf(was, size, "light sampling %s", hd->light_sampling ? "on" : "off");
        snprintf(is, size, "light sampling %s", id->light_sampling ? "on" : "off");
    } else if (hd->sampler != id->sampler) {
        snprintf(was, size, "sampler %s", NAME_OF(sampler_kind_names, hd->sampler));
        snprintf(is, size, "sampler %s", NAME_OF(sampler_kind_names, id->sampler));
    } else if (memcmp(&hd->noise_threshold, &id->noise_threshold, sizeof hd->noise_threshold) != 0) {
        snprintf(was, size, "noise threshold %.9g", (double)hd->noise_threshold);
        snprintf(is, size, "noise threshold %.9g", (double)id->noise_threshold);
    } else {
        return false;
    }
    return true;
}

typedef struct reader {
    FILE *f;
    const char *path;
    glint_error *err;
    uint64_t hash;
} reader;

static glint_status corrupt(const reader *r, const char *what) {
    snprintf(r->err->message, sizeof r->err->message, "%s: corrupt checkpoint (%s), expected a file written by glint's "
             "--checkpoint", r->path, what);
    return GLINT_ERR_INPUT;
}

// Reads n bytes into data (the size was checked, so a short read is an I/O error or a file cut meanwhile).
static bool take(reader *r, void *data, size_t n) {
    if (fread(data, 1, n, r->f) != n) return false;
    r->hash = hash_bytes(r->hash, data, n);
    return true;
}

// Hashes n bytes of a plane nobody asked for, without keeping them.
static bool skip(reader *r, uint64_t n) {
    unsigned char buf[4096];
    while (n > 0) {
        size_t part = n < sizeof buf ? (size_t)n : sizeof buf;
        if (!take(r, buf, part)) return false;
        n -= part;
    }
    return true;
}

// What is wrong with a plane's values, NULL when nothing: counts of samples are at most the spp the file was made
// for, sums of samples are finite and not negative (radiance is never negative).
static const char *plane_values_bad(const checkpoint_plane *p, size_t pixels, int32_t spp) {
    size_t n = pixels * p->components;
    if (p->type == CHECKPOINT_U32) {
        const uint32_t *v = p->data;
        for (size_t i = 0; i < n; i++)
            if (v[i] > (uint32_t)spp) return "a count above the samples per pixel it was made for";
    } else {
        const double *v = p->data;
        for (size_t i = 0; i < n; i++)
            if (!(v[i] >= 0.0 && v[i] <= DBL_MAX)) return "a sum that is negative, infinite or not a number";
    }
    return NULL;
}

// A read that failed part-way: an I/O error, or a file cut short while it was read.
static glint_status io_failed(const reader *r) {
    snprintf(r->err->message, sizeof r->err->message, "%s: cannot read the checkpoint: %s", r->path,
             ferror(r->f) ? strerror(errno ? errno : EIO) : "the file was cut short while it was read");
    return GLINT_ERR_INPUT;
}

// The planes' data after a checked header and table: each plane the caller names into its buffer (the others
// skipped), the data's checksum, then the values themselves.
static glint_status read_planes(reader *r, const header *hd, const plane_entry *entries, checkpoint_plane *planes,
                                size_t plane_count) {
    uint64_t pixels = region_pixels(hd->region);
    // Each plane the caller names is one entry of the table (names are unique), of the same type and size.
    checkpoint_plane *dest_of[MAX_PLANES] = {NULL};
    for (size_t i = 0; i < plane_count; i++) {
        uint32_t j = 0;
        while (j < hd->plane_count && strcmp(entries[j].name, planes[i].name) != 0) j++;
        if (j == hd->plane_count || entries[j].type != (uint32_t)planes[i].type ||
            entries[j].components != planes[i].components) {
            snprintf(r->err->message, sizeof r->err->message, "%s: the checkpoint has no plane \"%s\" of %u %s "
                     "values a pixel, which this render needs", r->path, planes[i].name, planes[i].components,
                     planes[i].type == CHECKPOINT_U32 ? "integer" : "floating-point");
            return GLINT_ERR_INPUT;
        }
        dest_of[j] = &planes[i];
    }

    // The data, each plane into the caller's buffer or skipped, and its checksum.
    r->hash = HASH_START;
    for (uint32_t j = 0; j < hd->plane_count; j++) {
        size_t bytes = (size_t)(pixels * entries[j].components * type_size(entries[j].type));
        if (!(dest_of[j] ? take(r, dest_of[j]->data, bytes) : skip(r, bytes))) return io_failed(r);
    }
    uint64_t data_hash, expected_data_hash = r->hash;
    if (fread(&data_hash, 1, sizeof data_hash, r->f) != sizeof data_hash) return io_failed(r);
    if (data_hash != expected_data_hash) return corrupt(r, "data checksum mismatch");
    // The checksums are no seal (anyone can recompute them): the values must be what a render can have made.
    for (size_t i = 0; i < plane_count; i++) {
        const char *bad = plane_values_bad(&planes[i], (size_t)pixels, hd->spp);
        if (bad) {
            snprintf(r->err->message, sizeof r->err->message, "%s: corrupt checkpoint (plane \"%s\": %s), expected a "
                     "file written by glint's --checkpoint", r->path, planes[i].name, bad);
            return GLINT_ERR_INPUT;
        }
    }
    return GLINT_OK;
}

static glint_status read_checkpoint(reader *r, const checkpoint_identity *id, checkpoint_plane *planes,
                                    size_t plane_count, int *spp, uint64_t file_size) {
    header hd;
    char name[NAME_MAX_BYTES + 1];
    plane_entry entries[MAX_PLANES];
    if (file_size < sizeof MAGIC || !take(r, &hd, file_size < sizeof hd ? file_size : sizeof hd) ||
        memcmp(hd.magic, MAGIC, sizeof MAGIC) != 0) {
        snprintf(r->err->message, sizeof r->err->message, "%s: not a glint checkpoint (no GLINTCKP signature), "
                 "expected a file written by glint's --checkpoint", r->path);
        return GLINT_ERR_INPUT;
    }
    if (file_size < sizeof hd) return corrupt(r, "truncated header");
    if (hd.byte_order != BYTE_ORDER_MARK) {
        snprintf(r->err->message, sizeof r->err->message, "%s: checkpoint written on a machine of another byte order, "
                 "expected one of this machine", r->path);
        return GLINT_ERR_INPUT;
    }
    if (hd.version != CHECKPOINT_VERSION) {
        snprintf(r->err->message, sizeof r->err->message, "%s: checkpoint of format version %u, this glint reads "
                 "version %u", r->path, hd.version, CHECKPOINT_VERSION);
        return GLINT_ERR_INPUT;
    }
    if (hd.name_bytes > NAME_MAX_BYTES || hd.plane_count > MAX_PLANES) return corrupt(r, "header out of range");
    uint64_t table = sizeof hd + hd.name_bytes + (uint64_t)hd.plane_count * sizeof(plane_entry) + 8u;
    if (file_size < table) return corrupt(r, "truncated header");
    uint64_t header_hash;
    if (!take(r, name, hd.name_bytes) || !take(r, entries, hd.plane_count * sizeof(plane_entry))) goto io_error;
    name[hd.name_bytes] = '\0';
    uint64_t expected_header_hash = r->hash;
    if (fread(&header_hash, 1, sizeof header_hash, r->f) != sizeof header_hash) goto io_error;
    if (header_hash != expected_header_hash) return corrupt(r, "header checksum mismatch");

    // The header is what was written: its sizes say how long the file is. Sizes are bounded first (no render is
    // larger than SCENE_MAX_DIMENSION a side), so that the length below cannot wrap around.
    if (hd.width < 1 || hd.height < 1 || hd.width > SCENE_MAX_DIMENSION || hd.height > SCENE_MAX_DIMENSION ||
        hd.region[0] < 0 || hd.region[1] < 0 || hd.region[0] >= hd.region[2] || hd.region[1] >= hd.region[3] ||
        hd.region[2] > hd.width || hd.region[3] > hd.height || hd.spp < 1 || hd.complete < 0 || hd.complete > hd.spp)
        return corrupt(r, "header out of range");
    uint64_t pixels = region_pixels(hd.region), expected = table + 8u;
    for (uint32_t i = 0; i < hd.plane_count; i++) {
        size_t t = type_size(entries[i].type);
        if (t == 0 || entries[i].components == 0 || entries[i].components > 64) return corrupt(r, "unknown plane type");
        if (!memchr(entries[i].name, '\0', PLANE_NAME_BYTES)) return corrupt(r, "plane name not terminated");
        for (uint32_t j = 0; j < i; j++)
            if (strcmp(entries[i].name, entries[j].name) == 0) return corrupt(r, "a plane listed twice");
        expected += pixels * entries[i].components * t;
    }
    if (file_size != expected) {
        snprintf(r->err->message, sizeof r->err->message, "%s: %s checkpoint: %llu bytes, expected %llu", r->path,
                 file_size < expected ? "truncated" : "corrupt", (unsigned long long)file_size,
                 (unsigned long long)expected);
        return GLINT_ERR_INPUT;
    }

    // Only now the render is compared: each setting by name, then the scene's files.
    char was[96], is[96];
    if (first_difference(&hd, id, was, is, sizeof was)) {
        snprintf(r->err->message, sizeof r->err->message, "%s: checkpoint of another render: it was made for %.300s with "
                 "%s, this render has %s; only --spp may change on resuming", r->path, name, was, is);
        return GLINT_ERR_INPUT;
    }
    if (hd.scene_hash != id->scene_hash) {
        snprintf(r->err->message, sizeof r->err->message, "%s: checkpoint of another scene: it was made for %.300s, "
                 "and this render's scene %s or a file it reads (mesh, material library, texture, environment map) "
                 "is not the same", r->path, name, id->scene_name);
        return GLINT_ERR_INPUT;
    }
    glint_status status = read_planes(r, &hd, entries, planes, plane_count);
    if (status == GLINT_OK) *spp = hd.spp;
    return status;

io_error:
    return io_failed(r);
}

// The checkpoint at path opened for reading; NULL with the message written when it cannot be.
static FILE *open_checkpoint(const char *path, struct stat *st, glint_status *status, glint_error *err) {
    int e = 0;
    FILE *f = filepath_open_regular(path, st, &e);
    if (!f) {
        snprintf(err->message, sizeof err->message, "%s: cannot open the checkpoint: %s, expected a file written by "
                 "glint's --checkpoint", path, filepath_problem_text(e));
        *status = e == ENOMEM ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
    }
    return f;
}

glint_status checkpoint_check_readable(const char *path, glint_error *err) {
    struct stat st;
    glint_status status = GLINT_OK;
    FILE *f = open_checkpoint(path, &st, &status, err);
    if (f) fclose(f);
    return status;
}

glint_status checkpoint_read(const char *path, const checkpoint_identity *id, checkpoint_plane *planes,
                             size_t plane_count, int *spp, glint_error *err) {
    struct stat st;
    glint_status status = GLINT_OK;
    FILE *f = open_checkpoint(path, &st, &status, err);
    if (!f) return status;
    reader r = {f, path, err, HASH_START};
    status = read_checkpoint(&r, id, planes, plane_count, spp, (uint64_t)st.st_size);
    fclose(f);
    return status;
}
