/* exr.c - OpenEXR through OpenEXR's C library: linear float RGB, written
 * to our atomic file, with what made the image (the rt_text the PNG keeps
 * in text chunks) as string attributes that exrheader shows. */
#include <errno.h>
#include <openexr.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "formats.h"
#include "status.h"

/* OpenEXR writes at given offsets (pwrite semantics); we hand it the
 * atomic temporary file's descriptor and keep the errno of a failure. */
typedef struct exr_sink {
    int fd, err;
} exr_sink;

static int64_t exr_write_fd(exr_const_context_t ctxt, void *user, const void *buf, uint64_t sz, uint64_t offset,
                            exr_stream_error_func_ptr_t error_cb)
{
    exr_sink *sink = user;
    int fd = sink->fd;
    const uint8_t *p = buf;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pwrite(fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            sink->err = n < 0 ? errno : EIO;
            error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed");
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)sz;
}

/* Modules never print: OpenEXR's messages are dropped, its codes kept. */
static void exr_quiet(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    (void)code;
    (void)msg;
}

/* Float R, G, B channels, ZIP (lossless), scanlines from the top; the
 * texts as string attributes of the part. */
static exr_result_t exr_encode_all(exr_context_t ctx, const float *rgb, uint32_t width, uint32_t height,
                                   const rt_image_write_opts *o)
{
    int part;
    exr_result_t rv = exr_add_part(ctx, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (!rv)
        rv = exr_initialize_required_attr_simple(ctx, part, (int32_t)width, (int32_t)height, EXR_COMPRESSION_ZIP);
    static const char *const names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3 && !rv; c++)
        rv = exr_add_channel(ctx, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    for (int i = 0; o && i < o->n_text && !rv; i++)
        rv = exr_attr_set_string(ctx, part, o->text[i].key, o->text[i].value);
    if (!rv)
        rv = exr_write_header(ctx);
    int32_t lines = 0;
    if (!rv)
        rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
    if (!rv && lines <= 0)
        rv = EXR_ERR_INVALID_ARGUMENT;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int32_t y = 0; y < (int32_t)height && !rv; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctx, part, y, &ci);
        if (!rv)
            rv = started ? exr_encoding_update(ctx, part, &ci, &enc) : exr_encoding_initialize(ctx, part, &ci, &enc);
        for (int16_t k = 0; k < enc.channel_count && !rv; k++) {
            exr_coding_channel_info_t *ch = &enc.channels[k];
            int c = ch->channel_name[0] == 'R' ? 0 : ch->channel_name[0] == 'G' ? 1 : 2;
            ch->encode_from_ptr = (const uint8_t *)(rgb + ((size_t)ci.start_y * width) * 3 + c);
            ch->user_pixel_stride = 3 * sizeof(float);
            ch->user_line_stride = (int32_t)(3 * sizeof(float) * width);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = sizeof(float);
        }
        if (!rv && !started) {
            started = 1;
            rv = exr_encoding_choose_default_routines(ctx, part, &enc);
        }
        if (!rv)
            rv = exr_encoding_run(ctx, part, &enc);
    }
    if (started) {
        exr_result_t r2 = exr_encoding_destroy(ctx, &enc);
        if (!rv)
            rv = r2;
    }
    return rv;
}

static int exr_write(const char *path, const float *rgb, uint32_t width, uint32_t height,
                     const rt_image_write_opts *o)
{
    if (!width || !height || width > INT32_MAX || height > INT32_MAX)
        return RT_EINVAL;
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (st)
        return st;
    exr_sink sink = {fileno(f.fp), 0};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &sink;
    init.write_fn = exr_write_fd;
    init.error_handler_fn = exr_quiet;
    init.max_image_width = (int)width;
    init.max_image_height = (int)height;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (!rv)
        rv = exr_encode_all(ctx, rgb, width, height, o);
    /* exr_finish writes the chunk offset table: its result counts too. */
    exr_result_t fin = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (rv || fin) {
        rt_atomic_abort(&f);
        if (sink.err)
            return rt_status_from_errno(sink.err);
        return (rv ? rv : fin) == EXR_ERR_OUT_OF_MEMORY ? RT_ENOMEM : RT_EIO;
    }
    return rt_atomic_commit(&f);
}


static int write_exr(const char *path, const void *px, uint32_t width, uint32_t height, const rt_image_write_opts *o)
{
    return exr_write(path, px, width, height, o);
}

const rt_format rt_format_exr = {.id = RT_FORMAT_EXR, .ext = ".exr", .linear = 1, .write = write_exr};
