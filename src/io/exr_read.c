// exr_read.c — OpenEXR files through the core C API, read through the descriptor the caller opened and checked:
// the header is checked (storage, size, channels) before anything is allocated, then each chunk (a block of
// scanlines or a tile) is checked against the data window and the file's size and decoded straight into the
// caller's floats, the library converting half and uint to float.
#include "io/exr_read.h"

#include <openexr.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

bool exr_read_is_exr(const unsigned char *head, size_t size) {
    return size >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01;
}

// The file the library reads through the caller's descriptor, and the first message the library reported.
typedef struct exr_source {
    int fd;
    int64_t size;
    char kept[256];
} exr_source;

struct exr_part {
    exr_context_t ctx;
    exr_source src;
    const char *path;
    exr_storage_t storage;
    int x0, y0, width, height; ///< the data window
    exr_channel *channels;
    int channel_count;
};

// The library reports errors through this; the first message is kept for the caller, nothing is printed.
static void keep_error(exr_const_context_t ctx, exr_result_t code, const char *msg) {
    (void)code;
    void *user = NULL;
    if (exr_get_user_data(ctx, &user) != EXR_ERR_SUCCESS || !user) return;
    exr_source *src = user;
    if (!src->kept[0]) snprintf(src->kept, sizeof src->kept, "%s", msg ? msg : "");
}

// pread semantics, as the library asks: up to sz bytes at offset, fewer only at the end of the file.
static int64_t read_source(exr_const_context_t ctx, void *user, void *buffer, uint64_t sz, uint64_t offset,
                           exr_stream_error_func_ptr_t error_cb) {
    const exr_source *src = user;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pread(src->fd, (char *)buffer + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            error_cb(ctx, EXR_ERR_READ_IO, "cannot read: %s", strerror(errno));
            return -1;
        }
        if (n == 0) break;
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t source_size(exr_const_context_t ctx, void *user) {
    (void)ctx;
    return ((const exr_source *)user)->size;
}

// "path: what: the library's words" for a failed call, GLINT_ERR_RENDER when memory ran out.
static glint_status fail(const char *path, const char *what, exr_result_t rv, const char *kept, glint_error *err) {
    const char *words = kept[0] ? kept : exr_get_default_error_message(rv);
    snprintf(err->message, sizeof err->message, "%s: %s: %s", path, what, words);
    return rv == EXR_ERR_OUT_OF_MEMORY ? GLINT_ERR_RENDER : GLINT_ERR_INPUT;
}

// Decodes one chunk whose first pixel is (cx, cy) of the data window into the targets; a chunk that claims to
// reach outside the data window is corrupt.
static exr_result_t decode_chunk(const exr_part *p, const exr_chunk_info_t *ci, int cx, int cy,
                                 const exr_channel_target *targets) {
    if (cx < 0 || cy < 0 || ci->width < 0 || ci->height < 0 || cx + ci->width > p->width ||
        cy + ci->height > p->height)
        return EXR_ERR_CORRUPT_CHUNK;
    // The library decodes a chunk shorter than its pixels without a word (the rest stays black): a chunk must lie
    // inside the file, and an uncompressed one must hold all its pixels.
    uint64_t file_size = (uint64_t)p->src.size;
    if (ci->data_offset > file_size || ci->packed_size > file_size - ci->data_offset ||
        (ci->compression == EXR_COMPRESSION_NONE && ci->packed_size != ci->unpacked_size))
        return EXR_ERR_CORRUPT_CHUNK;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    exr_result_t rv = exr_decoding_initialize(p->ctx, 0, ci, &dec);
    for (int16_t c = 0; rv == EXR_ERR_SUCCESS && c < dec.channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec.channels[c];
        ch->decode_to_ptr = NULL; // channels without a target are skipped
        const exr_channel_target *t = NULL;
        for (int i = 0; i < p->channel_count && !t; i++)
            if (strcmp(p->channels[i].name, ch->channel_name) == 0) t = &targets[i];
        if (!t || !t->base) continue;
        size_t at = (size_t)cy * t->line_stride + (size_t)cx * t->pixel_stride;
        ch->decode_to_ptr = (uint8_t *)(t->base + at);
        ch->user_pixel_stride = (int32_t)(t->pixel_stride * sizeof(float));
        ch->user_line_stride = (int32_t)(t->line_stride * sizeof(float));
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_choose_default_routines(p->ctx, 0, &dec);
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(p->ctx, 0, &dec);
    exr_decoding_destroy(p->ctx, &dec);
    return rv;
}

// Decodes every chunk of part 0: blocks of scanlines, or the tiles of the full-resolution level.
static exr_result_t decode_all(const exr_part *p, const exr_channel_target *targets) {
    exr_result_t rv = EXR_ERR_SUCCESS;
    if (p->storage == EXR_STORAGE_SCANLINE) {
        int32_t lines = 1;
        rv = exr_get_scanlines_per_chunk(p->ctx, 0, &lines);
        for (int y = 0; rv == EXR_ERR_SUCCESS && y < p->height; y += lines > 0 ? lines : 1) {
            exr_chunk_info_t ci;
            rv = exr_read_scanline_chunk_info(p->ctx, 0, p->y0 + y, &ci);
            // A scanline chunk's start_y is in file coordinates.
            if (rv == EXR_ERR_SUCCESS) rv = decode_chunk(p, &ci, 0, ci.start_y - p->y0, targets);
        }
        return rv;
    }
    int32_t tile_w = 0, tile_h = 0, level_w = 0, level_h = 0;
    rv = exr_get_tile_sizes(p->ctx, 0, 0, 0, &tile_w, &tile_h);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_level_sizes(p->ctx, 0, 0, 0, &level_w, &level_h);
    if (rv == EXR_ERR_SUCCESS && (tile_w <= 0 || tile_h <= 0)) rv = EXR_ERR_BAD_CHUNK_LEADER;
    int32_t tiles_x = rv == EXR_ERR_SUCCESS ? (level_w + tile_w - 1) / tile_w : 0;
    int32_t tiles_y = rv == EXR_ERR_SUCCESS ? (level_h + tile_h - 1) / tile_h : 0;
    for (int ty = 0; rv == EXR_ERR_SUCCESS && ty < tiles_y; ty++)
        for (int tx = 0; rv == EXR_ERR_SUCCESS && tx < tiles_x; tx++) {
            exr_chunk_info_t ci;
            rv = exr_read_tile_chunk_info(p->ctx, 0, tx, ty, 0, 0, &ci);
            // A tile's start_x and start_y are its tile indices, not pixels.
            if (rv == EXR_ERR_SUCCESS) rv = decode_chunk(p, &ci, tx * tile_w, ty * tile_h, targets);
        }
    return rv;
}

// Checks part 0's header: flat storage, a data window of 1 to max_pixels pixels; fills p's window and channels
// and *info. Otherwise the message is written.
static glint_status check_header(exr_part *p, size_t max_pixels, exr_part_info *info, glint_error *err) {
    const char *path = p->path;
    exr_result_t rv = exr_get_storage(p->ctx, 0, &p->storage);
    if (rv != EXR_ERR_SUCCESS) return fail(path, "unreadable header", rv, p->src.kept, err);
    if (p->storage != EXR_STORAGE_SCANLINE && p->storage != EXR_STORAGE_TILED) {
        snprintf(err->message, sizeof err->message, "%s: deep EXR images are not supported, expected a flat image", path);
        return GLINT_ERR_INPUT;
    }
    exr_attr_box2i_t dw, disp;
    const exr_attr_chlist_t *channels = NULL;
    int parts = 0;
    if ((rv = exr_get_data_window(p->ctx, 0, &dw)) != EXR_ERR_SUCCESS ||
        (rv = exr_get_display_window(p->ctx, 0, &disp)) != EXR_ERR_SUCCESS ||
        (rv = exr_get_channels(p->ctx, 0, &channels)) != EXR_ERR_SUCCESS || (rv = exr_get_count(p->ctx, &parts)))
        return fail(path, "unreadable header", rv, p->src.kept, err);
    long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || (unsigned long long)w * (unsigned long long)h > max_pixels) {
        snprintf(err->message, sizeof err->message, "%s: the image is %lldx%lld pixels; 1 to %zu pixels are allowed",
                 path, w, h, max_pixels);
        return GLINT_ERR_INPUT;
    }
    p->channels = calloc(channels->num_channels > 0 ? (size_t)channels->num_channels : 1u, sizeof *p->channels);
    if (!p->channels) {
        snprintf(err->message, sizeof err->message, "%s: out of memory", path);
        return GLINT_ERR_RENDER;
    }
    p->channel_count = channels->num_channels;
    for (int c = 0; c < channels->num_channels; c++) {
        const exr_attr_chlist_entry_t *e = &channels->entries[c];
        p->channels[c] = (exr_channel){e->name.str,
                                       e->pixel_type == EXR_PIXEL_HALF    ? EXR_CHANNEL_HALF
                                       : e->pixel_type == EXR_PIXEL_FLOAT ? EXR_CHANNEL_FLOAT
                                                                          : EXR_CHANNEL_UINT,
                                       e->x_sampling != 1 || e->y_sampling != 1};
    }
    p->x0 = dw.min.x;
    p->y0 = dw.min.y;
    p->width = (int)w;
    p->height = (int)h;
    // The windows as X0, Y0, X1, Y1 (exclusive); a display window beyond int's range is saturated, for the
    // caller to refuse.
    long long box[2][4] = {{disp.min.x, disp.min.y, (long long)disp.max.x + 1, (long long)disp.max.y + 1},
                           {dw.min.x, dw.min.y, (long long)dw.max.x + 1, (long long)dw.max.y + 1}};
    for (int k = 0; k < 4; k++) {
        info->display[k] = box[0][k] > 0x7fffffff ? 0x7fffffff : (int)box[0][k];
        info->data[k] = box[1][k] > 0x7fffffff ? 0x7fffffff : (int)box[1][k];
    }
    info->parts = parts;
    info->channel_count = p->channel_count;
    info->channels = p->channels;
    return GLINT_OK;
}

glint_status exr_part_open(FILE *f, const char *path, size_t max_pixels, exr_part **out, exr_part_info *info,
                           glint_error *err) {
    *out = NULL;
    memset(info, 0, sizeof *info);
    exr_part *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(err->message, sizeof err->message, "%s: out of memory", path);
        return GLINT_ERR_RENDER;
    }
    p->path = path;
    p->src.fd = fileno(f);
    struct stat st;
    if (fstat(p->src.fd, &st) != 0) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno));
        free(p);
        return GLINT_ERR_INPUT;
    }
    p->src.size = (int64_t)st.st_size;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &p->src;
    init.error_handler_fn = keep_error;
    init.read_fn = read_source;
    init.size_fn = source_size;
    exr_result_t rv = exr_start_read(&p->ctx, path, &init);
    glint_status status = rv == EXR_ERR_SUCCESS ? check_header(p, max_pixels, info, err)
                                                : fail(path, "unreadable OpenEXR header", rv, p->src.kept, err);
    if (status != GLINT_OK) {
        exr_part_close(p);
        memset(info, 0, sizeof *info);
        return status;
    }
    *out = p;
    return GLINT_OK;
}

glint_status exr_part_decode(exr_part *p, const exr_channel_target *targets, glint_error *err) {
    exr_result_t rv = decode_all(p, targets);
    return rv == EXR_ERR_SUCCESS ? GLINT_OK : fail(p->path, "corrupt OpenEXR data", rv, p->src.kept, err);
}

void exr_part_close(exr_part *p) {
    if (!p) return;
    if (p->ctx) exr_finish(&p->ctx);
    free(p->channels);
    free(p);
}

// Which of R, G, B (0..2) a channel fills; 3 for Y (grey); -1 for any other (not decoded).
static int channel_slot(const char *name) {
    static const char *const names[4] = {"R", "G", "B", "Y"};
    for (int k = 0; k < 4; k++)
        if (strcmp(name, names[k]) == 0) return k;
    return -1;
}

glint_status exr_read_open(FILE *f, const char *path, image_rgb *out, glint_error *err) {
    *out = (image_rgb){0};
    exr_part *p = NULL;
    exr_part_info info;
    glint_status status = exr_part_open(f, path, MAP_READ_MAX_PIXELS, &p, &info, err);
    if (status != GLINT_OK) return status;
    // R, G, B (or Y) at full resolution; other channels are not read.
    bool seen[4] = {false, false, false, false};
    for (int c = 0; c < info.channel_count; c++) {
        const exr_channel *e = &info.channels[c];
        int slot = channel_slot(e->name);
        if (slot < 0) continue;
        if (e->subsampled) {
            snprintf(err->message, sizeof err->message,
                     "%s: channel %s is subsampled; expected full-resolution R, G, B channels", path, e->name);
            exr_part_close(p);
            return GLINT_ERR_INPUT;
        }
        seen[slot] = true;
    }
    bool grey = !(seen[0] && seen[1] && seen[2]) && seen[3];
    if (!(seen[0] && seen[1] && seen[2]) && !seen[3]) {
        snprintf(err->message, sizeof err->message,
                 "%s: no R, G and B channels (nor a Y channel) in the first part; expected an RGB image", path);
        exr_part_close(p);
        return GLINT_ERR_INPUT;
    }
    size_t n = (size_t)p->width * (size_t)p->height * 3u;
    float *rgb = calloc(n, sizeof *rgb); // channels a file lacks stay black
    exr_channel_target *targets = calloc((size_t)info.channel_count + 1u, sizeof *targets);
    if (!rgb || !targets) {
        snprintf(err->message, sizeof err->message, "%s: out of memory for a %dx%d image", path, p->width, p->height);
        free(rgb);
        free(targets);
        exr_part_close(p);
        return GLINT_ERR_RENDER;
    }
    // Y alone fills R (and is copied to G and B below); beside R, G and B it is skipped.
    for (int c = 0; c < info.channel_count; c++) {
        int slot = channel_slot(info.channels[c].name);
        if (slot < 0 || (slot == 3 && !grey)) continue;
        targets[c] = (exr_channel_target){rgb + (slot == 3 ? 0 : slot), 3, 3u * (size_t)p->width};
    }
    status = exr_part_decode(p, targets, err);
    int width = p->width, height = p->height;
    free(targets);
    exr_part_close(p);
    if (status != GLINT_OK) {
        free(rgb);
        return status;
    }
    for (size_t i = 0; i < n; i += 3) {
        if (grey) rgb[i + 1] = rgb[i + 2] = rgb[i];
        // Linear radiance: a non-finite or negative value would poison every sample that sees it.
        for (int c = 0; c < 3; c++)
            if (!(rgb[i + (size_t)c] >= 0.0f) || rgb[i + (size_t)c] > 3.4e38f) rgb[i + (size_t)c] = 0.0f;
    }
    out->width = width;
    out->height = height;
    out->pixels = rgb;
    return GLINT_OK;
}
