// exr_write.c — EXR files through OpenEXR's core C API: the header, then each block of scanlines encoded
// from the image's interleaved RGB floats (the library converts to half where asked), written through a
// stream function so that the file goes wherever image_write's atomic scheme put it.
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

int exr_write(FILE *f, const glint_image *img, bool half, char *why, size_t why_size) {
    exr_sink sink = {f, 0, {0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &sink;
    init.write_fn = sink_write;
    init.error_handler_fn = keep_error;
    exr_context_t ctx = NULL;
    int part = 0;
    exr_result_t rv = exr_start_write(&ctx, "image.exr", EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(ctx, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctx, part, img->width, img->height, EXR_COMPRESSION_ZIP);
    static const char *const names[3] = {"R", "G", "B"};
    for (int c = 0; rv == EXR_ERR_SUCCESS && c < 3; c++)
        rv = exr_add_channel(ctx, part, names[c], half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
    int32_t lines = 1;
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
    for (int y = 0; rv == EXR_ERR_SUCCESS && y < img->height; y += lines) {
        exr_chunk_info_t info;
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        rv = exr_write_scanline_chunk_info(ctx, part, y, &info);
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_initialize(ctx, part, &info, &enc);
        if (rv != EXR_ERR_SUCCESS) break;
        // Each channel reads its component of the interleaved RGB rows of this block.
        for (int16_t c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            int k = ch->channel_name[0] == 'R' ? 0 : ch->channel_name[0] == 'G' ? 1 : 2;
            size_t first = (size_t)info.start_y * (size_t)img->width * 3u + (size_t)k;
            ch->encode_from_ptr = (const uint8_t *)(img->rgb + first);
            ch->user_pixel_stride = (int32_t)(3 * sizeof(float));
            ch->user_line_stride = (int32_t)(3 * sizeof(float) * (size_t)img->width);
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
