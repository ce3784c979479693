// exr_write.c — EXR files through OpenEXR's core C API: the header, then each block of scanlines encoded
// from the image's interleaved RGB floats and its AOV planes (the library converts to half where asked), written
// through a stream function so that the file goes wherever image_write's atomic scheme put it.
#include "io/exr_write.h"
#include "film/film.h"

#include <openexr.h>

#include <errno.h>
#include <string.h>
#include <sys/types.h>

// Where the library's writes go: the open file, at the offsets it asks for (it writes the offset table last).
typedef struct exr_sink {
    FILE *f;
    int error;            ///< the first errno of a failed write
    char message[256];    ///< the library's first error message
} exr_sink;

static int64_t sink_write(exr_const_context_t ctx, void *user, const void *buf, uint64_t size, uint64_t offset,
                          exr_stream_error_func_ptr_t error_cb) {
    (void)ctx;
    (void)error_cb;
    exr_sink *s = user;
    if (fseeko(s->f, (off_t)offset, SEEK_SET) != 0 || fwrite(buf, 1, (size_t)size, s->f) != (size_t)size) {
        if (!s->error) s->error = errno ? errno : EIO;
        return -1;
    }
    return (int64_t)size;
}

// The library reports errors through this; the first message is kept for the caller, nothing is printed.
static void keep_error(exr_const_context_t ctx, exr_result_t code, const char *msg) {
    (void)code;
    void *user = NULL;
    if (exr_get_user_data(ctx, &user) != EXR_ERR_SUCCESS || !user) return;
    exr_sink *s = user;
    if (!s->message[0]) snprintf(s->message, sizeof s->message, "%s", msg ? msg : "");
}

// One channel of the file: its name, and where its values lie in the image (every `stride` floats from `first`).
typedef struct exr_source {
    const char *name;
    const float *first;
    int stride;
    exr_pixel_type_t type;
} exr_source;

enum { EXR_MAX_CHANNELS = 11 }; // R, G, B, albedo.R/G/B, normal.X/Y/Z, Z, samples

// The channels of img: R, G, B, then those of its AOV planes. Depth and the sample count stay 32-bit even in a half
// file: half floats hold only 11 significant bits, too few for distances and counts.
static int exr_sources(const glint_image *img, bool half, exr_source out[EXR_MAX_CHANNELS]) {
    static const char *const names[FILM_AOV_COUNT + 1][3] = {
        {"R", "G", "B"}, {"albedo.R", "albedo.G", "albedo.B"}, {"normal.X", "normal.Y", "normal.Z"}, {"Z", NULL, NULL},
        {"samples", NULL, NULL}};
    exr_pixel_type_t colour = half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
    int n = 0;
    for (int plane = 0; plane <= FILM_AOV_COUNT; plane++) {
        const float *data = plane == 0 ? img->rgb : img->aov[plane - 1];
        int stride = plane == 0 ? 3 : film_aov_channels(plane - 1);
        if (!data) continue;
        for (int c = 0; c < stride; c++)
            out[n++] = (exr_source){names[plane][c], data + c, stride,
                                    plane - 1 >= FILM_AOV_DEPTH ? EXR_PIXEL_FLOAT : colour};
    }
    return n;
}

// The header's windows: the data window is where the image's pixels lie in the display window, the full image
// (a region's EXR records both, as renderers' crop windows do).
static exr_result_t exr_header(exr_context_t ctx, int part, const glint_image *img) {
    exr_attr_box2i_t display, data;
    display.min.x = display.min.y = 0;
    display.max.x = img->full_width - 1;
    display.max.y = img->full_height - 1;
    data.min.x = img->x0;
    data.min.y = img->y0;
    data.max.x = img->x0 + img->width - 1;
    data.max.y = img->y0 + img->height - 1;
    exr_attr_v2f_t center;
    center.x = center.y = 0.0f;
    return exr_initialize_required_attr(ctx, part, &display, &data, 1.0f, &center, 1.0f, EXR_LINEORDER_INCREASING_Y,
                                        EXR_COMPRESSION_ZIP);
}

int exr_write(FILE *f, const glint_image *img, bool half, char *why, size_t why_size) {
    exr_sink sink = {f, 0, {0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &sink;
    init.write_fn = sink_write;
    init.error_handler_fn = keep_error;
    exr_context_t ctx = NULL;
    int part = 0;
    exr_source sources[EXR_MAX_CHANNELS];
    int count = exr_sources(img, half, sources);
    exr_result_t rv = exr_start_write(&ctx, "image.exr", EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctx, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS) rv = exr_header(ctx, part, img);
    for (int c = 0; rv == EXR_ERR_SUCCESS && c < count; c++)
        rv = exr_add_channel(ctx, part, sources[c].name, sources[c].type,
                             c < 3 ? EXR_PERCEPTUALLY_LOGARITHMIC : EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
    int32_t lines = 1;
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
    for (int y = 0; rv == EXR_ERR_SUCCESS && y < img->height; y += lines) {
        exr_chunk_info_t info;
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        rv = exr_write_scanline_chunk_info(ctx, part, img->y0 + y, &info);
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_initialize(ctx, part, &info, &enc);
        if (rv != EXR_ERR_SUCCESS) break;
        // The library gives the channels in the file's (sorted) order: each reads its source's rows of this block.
        for (int16_t c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            const exr_source *src = &sources[0];
            for (int i = 0; i < count; i++)
                if (strcmp(sources[i].name, ch->channel_name) == 0) src = &sources[i];
            size_t row = (size_t)(info.start_y - img->y0) * (size_t)img->width * (size_t)src->stride;
            ch->encode_from_ptr = (const uint8_t *)(src->first + row);
            ch->user_pixel_stride = (int32_t)((size_t)src->stride * sizeof(float));
            ch->user_line_stride = (int32_t)((size_t)src->stride * sizeof(float) * (size_t)img->width);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
        }
        rv = exr_encoding_choose_default_routines(ctx, part, &enc);
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, part, &enc);
        exr_result_t rd = exr_encoding_destroy(ctx, &enc);
        if (rv == EXR_ERR_SUCCESS) rv = rd;
    }
    exr_result_t rf = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (rv == EXR_ERR_SUCCESS) rv = rf;
    if (rv == EXR_ERR_SUCCESS && !sink.error) return 0;
    snprintf(why, why_size, "%s", sink.message[0] ? sink.message : exr_get_default_error_message(rv));
    return sink.error ? sink.error : EIO;
}
