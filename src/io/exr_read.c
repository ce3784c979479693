// exr_read.c — OpenEXR files through the core C API, read through the descriptor map_read opened and checked:
// the header is checked (storage, size, channels) before anything is allocated, then each chunk (a block of scanlines or a tile) is decoded straight into the
// interleaved RGB floats, the library converting half and uint to float.
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

// The file the library reads through glint's descriptor (opened and checked by map_read), and the first
// message the library reported.
typedef struct exr_source {
    int fd;
    int64_t size;
    char kept[256];
} exr_source;

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

// Which of R, G, B (0..2) a channel fills; 3 for Y (grey); -1 for any other (not decoded).
static int channel_slot(const char *name) {
    static const char *const names[4] = {"R", "G", "B", "Y"};
    for (int k = 0; k < 4; k++)
        if (strcmp(name, names[k]) == 0) return k;
    return -1;
}

typedef struct exr_target {
    float *rgb;
    int x0, y0, width, height; ///< the data window
    bool grey;                 ///< Y alone fills R (and is copied to G and B); beside R, G and B it is skipped
    uint64_t file_size;        ///< every chunk's bytes must lie inside the file
} exr_target;

// Decodes one chunk whose first pixel is (cx, cy) of the data window into the target; a chunk that claims to
// reach outside the data window is corrupt.
static exr_result_t decode_chunk(exr_context_t ctx, const exr_chunk_info_t *ci, int cx, int cy, const exr_target *t) {
    if (cx < 0 || cy < 0 || ci->width < 0 || ci->height < 0 || cx + ci->width > t->width ||
        cy + ci->height > t->height)
        return EXR_ERR_CORRUPT_CHUNK;
    // The library decodes a chunk shorter than its pixels without a word (the rest stays black): a chunk must lie
    // inside the file, and an uncompressed one must hold all its pixels.
    if (ci->data_offset > t->file_size || ci->packed_size > t->file_size - ci->data_offset ||
        (ci->compression == EXR_COMPRESSION_NONE && ci->packed_size != ci->unpacked_size))
        return EXR_ERR_CORRUPT_CHUNK;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    exr_result_t rv = exr_decoding_initialize(ctx, 0, ci, &dec);
    for (int16_t c = 0; rv == EXR_ERR_SUCCESS && c < dec.channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec.channels[c];
        int slot = channel_slot(ch->channel_name);
        ch->decode_to_ptr = NULL; // channels other than R, G, B (or Y alone) are skipped
        if (slot < 0 || (slot == 3 && !t->grey)) continue;
        size_t at = ((size_t)cy * (size_t)t->width + (size_t)cx) * 3u + (size_t)(slot == 3 ? 0 : slot);
        ch->decode_to_ptr = (uint8_t *)(t->rgb + at);
        ch->user_pixel_stride = (int32_t)(3 * sizeof(float));
        ch->user_line_stride = (int32_t)(3 * sizeof(float) * (size_t)t->width);
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_choose_default_routines(ctx, 0, &dec);
    if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(ctx, 0, &dec);
    exr_decoding_destroy(ctx, &dec);
    return rv;
}

// Decodes every chunk of part 0: blocks of scanlines, or the tiles of the full-resolution level.
static exr_result_t decode_all(exr_context_t ctx, exr_storage_t storage, const exr_target *t) {
    exr_result_t rv = EXR_ERR_SUCCESS;
    if (storage == EXR_STORAGE_SCANLINE) {
        int32_t lines = 1;
        rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
        for (int y = 0; rv == EXR_ERR_SUCCESS && y < t->height; y += lines > 0 ? lines : 1) {
            exr_chunk_info_t ci;
            rv = exr_read_scanline_chunk_info(ctx, 0, t->y0 + y, &ci);
            // A scanline chunk's start_y is in file coordinates.
            if (rv == EXR_ERR_SUCCESS) rv = decode_chunk(ctx, &ci, 0, ci.start_y - t->y0, t);
        }
        return rv;
    }
    int32_t tile_w = 0, tile_h = 0, level_w = 0, level_h = 0;
    rv = exr_get_tile_sizes(ctx, 0, 0, 0, &tile_w, &tile_h);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_level_sizes(ctx, 0, 0, 0, &level_w, &level_h);
    if (rv == EXR_ERR_SUCCESS && (tile_w <= 0 || tile_h <= 0)) rv = EXR_ERR_BAD_CHUNK_LEADER;
    int32_t tiles_x = rv == EXR_ERR_SUCCESS ? (level_w + tile_w - 1) / tile_w : 0;
    int32_t tiles_y = rv == EXR_ERR_SUCCESS ? (level_h + tile_h - 1) / tile_h : 0;
    for (int ty = 0; rv == EXR_ERR_SUCCESS && ty < tiles_y; ty++)
        for (int tx = 0; rv == EXR_ERR_SUCCESS && tx < tiles_x; tx++) {
            exr_chunk_info_t ci;
            rv = exr_read_tile_chunk_info(ctx, 0, tx, ty, 0, 0, &ci);
            // A tile's start_x and start_y are its tile indices, not pixels.
            if (rv == EXR_ERR_SUCCESS) rv = decode_chunk(ctx, &ci, tx * tile_w, ty * tile_h, t);
        }
    return rv;
}

// Checks part 0's header: flat storage, a data window within the size limit, R, G, B (or Y) at full
// resolution. Fills the target's window and whether the image is grey; otherwise the message is written.
static glint_status check_header(exr_context_t ctx, const char *path, exr_storage_t *storage, exr_target *t,
                                 const char *kept, glint_error *err) {
    exr_result_t rv = exr_get_storage(ctx, 0, storage);
    if (rv != EXR_ERR_SUCCESS) return fail(path, "unreadable header", rv, kept, err);
    if (*storage != EXR_STORAGE_SCANLINE && *storage != EXR_STORAGE_TILED) {
        snprintf(err->message, sizeof err->message, "%s: deep EXR images are not supported, expected a flat image", path);
        return GLINT_ERR_INPUT;
    }
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *channels = NULL;
    if ((rv = exr_get_data_window(ctx, 0, &dw)) != EXR_ERR_SUCCESS || (rv = exr_get_channels(ctx, 0, &channels)))
        return fail(path, "unreadable header", rv, kept, err);
    long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || (unsigned long long)w * (unsigned long long)h > MAP_READ_MAX_PIXELS) {
        snprintf(err->message, sizeof err->message, "%s: the image is %lldx%lld pixels; 1 to %zu pixels are allowed",
                 path, w, h, (size_t)MAP_READ_MAX_PIXELS);
        return GLINT_ERR_INPUT;
    }
    bool seen[4] = {false, false, false, false};
    for (int c = 0; c < channels->num_channels; c++) {
        const exr_attr_chlist_entry_t *e = &channels->entries[c];
        int slot = channel_slot(e->name.str);
        if (slot < 0) continue;
        if (e->x_sampling != 1 || e->y_sampling != 1) {
            snprintf(err->message, sizeof err->message,
                     "%s: channel %s is subsampled (%dx%d); expected full-resolution R, G, B channels", path,
                     e->name.str, e->x_sampling, e->y_sampling);
            return GLINT_ERR_INPUT;
        }
        seen[slot] = true;
    }
    t->grey = !(seen[0] && seen[1] && seen[2]) && seen[3];
    if (!(seen[0] && seen[1] && seen[2]) && !seen[3]) {
        snprintf(err->message, sizeof err->message,
                 "%s: no R, G and B channels (nor a Y channel) in the first part; expected an RGB image", path);
        return GLINT_ERR_INPUT;
    }
    t->x0 = dw.min.x;
    t->y0 = dw.min.y;
    t->width = (int)w;
    t->height = (int)h;
    return GLINT_OK;
}

glint_status exr_read_open(FILE *f, const char *path, image_rgb *out, glint_error *err) {
    out->width = out->height = 0;
    out->pixels = NULL;
    struct stat st;
    exr_source src = {.fd = fileno(f)};
    if (fstat(src.fd, &st) != 0) {
        snprintf(err->message, sizeof err->message, "%s: cannot read: %s", path, strerror(errno));
        return GLINT_ERR_INPUT;
    }
    src.size = (int64_t)st.st_size;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &src;
    init.error_handler_fn = keep_error;
    init.read_fn = read_source;
    init.size_fn = source_size;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_read(&ctx, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&ctx);
        return fail(path, "unreadable OpenEXR header", rv, src.kept, err);
    }
    exr_storage_t storage;
    exr_target t = {.file_size = (uint64_t)src.size};
    glint_status status = check_header(ctx, path, &storage, &t, src.kept, err);
    if (status != GLINT_OK) {
        exr_finish(&ctx);
        return status;
    }
    size_t n = (size_t)t.width * (size_t)t.height * 3u;
    t.rgb = calloc(n, sizeof *t.rgb); // channels a file lacks stay black
    if (!t.rgb) {
        exr_finish(&ctx);
        snprintf(err->message, sizeof err->message, "%s: out of memory for a %dx%d image", path, t.width, t.height);
        return GLINT_ERR_RENDER;
    }
    rv = decode_all(ctx, storage, &t);
    exr_finish(&ctx);
    if (rv != EXR_ERR_SUCCESS) {
        free(t.rgb);
        return fail(path, "corrupt OpenEXR data", rv, src.kept, err);
    }
    for (size_t i = 0; i < n; i += 3) {
        if (t.grey) t.rgb[i + 1] = t.rgb[i + 2] = t.rgb[i];
        // Linear radiance: a non-finite or negative value would poison every sample that sees it.
        for (int c = 0; c < 3; c++)
            if (!(t.rgb[i + (size_t)c] >= 0.0f) || t.rgb[i + (size_t)c] > 3.4e38f) t.rgb[i + (size_t)c] = 0.0f;
    }
    out->width = t.width;
    out->height = t.height;
    out->pixels = t.rgb;
    return GLINT_OK;
}
