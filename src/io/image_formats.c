/* image_formats.c - PPM, BMP, PFM and OpenEXR writers, and the choice of
 * format by extension. Each writer goes through rt_atomic_* and checks
 * every write, so a failure leaves no file (and never a partial one). */
#include "image_formats.h"

#include <errno.h>
#include <openexr.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "fileio.h"
#include "image.h"
#include "status.h"

static const struct {
    const char *ext;
    rt_image_format fmt;
} EXTS[] = {
    {".png", RT_FORMAT_PNG}, {".ppm", RT_FORMAT_PPM}, {".bmp", RT_FORMAT_BMP},
    {".pfm", RT_FORMAT_PFM}, {".exr", RT_FORMAT_EXR},
};

rt_image_format rt_image_format_from_path(const char *path)
{
    size_t n = strlen(path);
    for (size_t i = 0; i < sizeof EXTS / sizeof EXTS[0]; i++) {
        size_t e = strlen(EXTS[i].ext);
        if (n > e && !strcasecmp(path + n - e, EXTS[i].ext))
            return EXTS[i].fmt;
    }
    return RT_FORMAT_UNKNOWN;
}

const char *rt_image_format_list(void) { return ".png, .ppm, .bmp, .pfm, .exr"; }

int rt_image_check_opts(rt_image_format fmt, const rt_image_write_opts *o)
{
    if (o->bit_depth != 8 && o->bit_depth != 16)
        return RT_EINVAL;
    if (o->bit_depth == 16 && fmt != RT_FORMAT_PNG && fmt != RT_FORMAT_PPM)
        return RT_EUNSUPPORTED;
    if (o->ppm_ascii && fmt != RT_FORMAT_PPM)
        return RT_EUNSUPPORTED;
    return fmt == RT_FORMAT_UNKNOWN ? RT_EUNSUPPORTED : RT_OK;
}

static int io_status(void) { return rt_status_from_errno(errno); }

/* Writes n bytes or aborts f; returns the status. */
static int put_bytes(rt_atomic_file *f, const void *p, size_t n)
{
    if (fwrite(p, 1, n, f->fp) == n)
        return RT_OK;
    int st = io_status();
    rt_atomic_abort(f);
    return st;
}

/* Opens the atomic file and writes the header; on failure nothing is left
 * and f needs no cleanup. */
static int start_file(rt_atomic_file *f, const char *path, const void *header, size_t n)
{
    int st = rt_atomic_open(f, path);
    return st ? st : put_bytes(f, header, n);
}

/* ---- PPM -------------------------------------------------------------- */

/* rgb: uint8_t samples for maxval 255, host-order uint16_t for 65535. */
static int ppm_write(const char *path, const void *rgb, uint32_t width, uint32_t height, int maxval, int ascii)
{
    if (!width || !height || (maxval != 255 && maxval != 65535))
        return RT_EINVAL;
    const int wide = maxval > 255;
    const size_t row_samples = (size_t)width * 3;
    uint8_t *row = ascii ? NULL : malloc(row_samples * (wide ? 2 : 1));
    if (!ascii && !row)
        return RT_ENOMEM;
    char head[64];
    int hn = snprintf(head, sizeof head, "%s\n%u %u\n%d\n", ascii ? "P3" : "P6", width, height, maxval);
    rt_atomic_file f;
    int st = start_file(&f, path, head, (size_t)hn);
    const uint8_t *p8 = rgb;
    const uint16_t *p16 = rgb;
    for (uint32_t y = 0; y < height && !st; y++) {
        size_t base = (size_t)y * row_samples;
        if (ascii) {
            /* The book's layout: one "r g b" line per pixel. */
            for (uint32_t x = 0; x < width && !st; x++) {
                size_t i = base + (size_t)x * 3;
                unsigned r = wide ? p16[i] : p8[i], g = wide ? p16[i + 1] : p8[i + 1],
                         b = wide ? p16[i + 2] : p8[i + 2];
                if (fprintf(f.fp, "%u %u %u\n", r, g, b) < 0) {
                    st = io_status();
                    rt_atomic_abort(&f);
                }
            }
        } else if (wide) {
            for (size_t i = 0; i < row_samples; i++) { /* PPM's 16-bit samples are big-endian */
                row[2 * i] = (uint8_t)(p16[base + i] >> 8);
                row[2 * i + 1] = (uint8_t)p16[base + i];
            }
            st = put_bytes(&f, row, row_samples * 2);
        } else {
            st = put_bytes(&f, p8 + base, row_samples);
        }
    }
    free(row);
    return st ? st : rt_atomic_commit(&f);
}

/* ---- BMP -------------------------------------------------------------- */

static void le16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}
static void le32(uint8_t *p, uint32_t v)
{
    le16(p, v);
    le16(p + 2, v >> 16);
}

/* BITMAPFILEHEADER + BITMAPINFOHEADER, 24 bits, no compression, rows
 * bottom-up in B, G, R order, each padded to a multiple of 4 bytes. */
static int bmp_write(const char *path, const uint8_t *rgb, uint32_t width, uint32_t height)
{
    if (!width || !height || width > INT32_MAX || height > INT32_MAX)
        return RT_EINVAL;
    const uint64_t stride = ((uint64_t)width * 3 + 3) & ~(uint64_t)3;
    const uint64_t data = stride * height, total = 54 + data;
    if (total > UINT32_MAX)
        return RT_EOVERFLOW;
    uint8_t *row = calloc(1, (size_t)stride);
    if (!row)
        return RT_ENOMEM;
    uint8_t h[54] = {'B', 'M'};
    le32(h + 2, (uint32_t)total);
    le32(h + 10, 54);        /* pixel data offset */
    le32(h + 14, 40);        /* BITMAPINFOHEADER size */
    le32(h + 18, width);
    le32(h + 22, height);    /* positive: bottom-up */
    le16(h + 26, 1);         /* planes */
    le16(h + 28, 24);        /* bits per pixel */
    le32(h + 34, (uint32_t)data);
    le32(h + 38, 2835);      /* 72 dpi, as most writers put it */
    le32(h + 42, 2835);
    rt_atomic_file f;
    int st = start_file(&f, path, h, sizeof h);
    for (uint32_t y = height; y-- > 0 && !st;) {
        const uint8_t *src = rgb + (size_t)y * width * 3;
        for (uint32_t x = 0; x < width; x++) {
            row[3 * x] = src[3 * x + 2];
            row[3 * x + 1] = src[3 * x + 1];
            row[3 * x + 2] = src[3 * x];
        }
        st = put_bytes(&f, row, (size_t)stride);
    }
    free(row);
    return st ? st : rt_atomic_commit(&f);
}

/* ---- PFM -------------------------------------------------------------- */

/* Colour PFM: "PF", size, a negative scale for little-endian floats, then
 * rows from the bottom up. */
static int pfm_write(const char *path, const float *rgb, uint32_t width, uint32_t height)
{
    if (!width || !height)
        return RT_EINVAL;
    const size_t row_samples = (size_t)width * 3;
    uint8_t *row = malloc(row_samples * 4);
    if (!row)
        return RT_ENOMEM;
    char head[64];
    int hn = snprintf(head, sizeof head, "PF\n%u %u\n-1.0\n", width, height);
    rt_atomic_file f;
    int st = start_file(&f, path, head, (size_t)hn);
    for (uint32_t y = height; y-- > 0 && !st;) {
        for (size_t i = 0; i < row_samples; i++) {
            uint32_t bits;
            memcpy(&bits, &rgb[(size_t)y * row_samples + i], 4);
            le32(row + 4 * i, bits);
        }
        st = put_bytes(&f, row, row_samples * 4);
    }
    free(row);
    return st ? st : rt_atomic_commit(&f);
}

/* ---- OpenEXR ---------------------------------------------------------- */

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

/* Float R, G, B channels, ZIP (lossless), scanlines from the top. */
static exr_result_t exr_encode_all(exr_context_t ctx, const float *rgb, uint32_t width, uint32_t height)
{
    int part;
    exr_result_t rv = exr_add_part(ctx, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (!rv)
        rv = exr_initialize_required_attr_simple(ctx, part, (int32_t)width, (int32_t)height, EXR_COMPRESSION_ZIP);
    static const char *const names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3 && !rv; c++)
        rv = exr_add_channel(ctx, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
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

static int exr_write(const char *path, const float *rgb, uint32_t width, uint32_t height)
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
        rv = exr_encode_all(ctx, rgb, width, height);
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

/* ---- dispatch --------------------------------------------------------- */

/* Tone maps (or keeps linear) row by row: rows may hold different numbers
 * of samples in a preview. */
static void convert_rows(const int64_t *acc, uint32_t width, uint32_t height, uint32_t samples,
                         const uint32_t *row_samples, int is_float, int bit_depth, uint8_t *px, size_t elem)
{
    const size_t row = (size_t)width * 3;
    for (uint32_t y = 0; y < height; y++) {
        uint32_t n = row_samples ? row_samples[y] : samples;
        const int64_t *src = acc + y * row;
        void *dst = px + y * row * elem;
        if (!n)
            memset(dst, 0, row * elem); /* also 0.0f */
        else if (is_float)
            rt_image_to_linear(src, width, n, dst);
        else if (bit_depth == 16)
            rt_image_to_rgb16(src, width, n, dst);
        else
            rt_image_to_rgb8(src, width, n, dst);
    }
}

static int write_any(const char *path, const int64_t *acc, uint32_t width, uint32_t height, uint32_t samples,
                     const uint32_t *row_samples, const rt_image_write_opts *o)
{
    rt_image_format fmt = rt_image_format_from_path(path);
    int st = rt_image_check_opts(fmt, o);
    if (st)
        return st;
    if (!width || !height || (!row_samples && !samples))
        return RT_EINVAL;
    const size_t n = (size_t)width * height;
    const int is_float = fmt == RT_FORMAT_PFM || fmt == RT_FORMAT_EXR;
    const size_t elem = is_float ? sizeof(float) : o->bit_depth == 16 ? sizeof(uint16_t) : 1;
    void *px = malloc(n * 3 * elem);
    if (!px)
        return RT_ENOMEM;
    convert_rows(acc, width, height, samples, row_samples, is_float, o->bit_depth, px, elem);
    switch (fmt) {
    case RT_FORMAT_PNG:
        st = rt_png_write(path, px, width, height, o->bit_depth, o->text, o->n_text);
        break;
    case RT_FORMAT_PPM:
        st = ppm_write(path, px, width, height, o->bit_depth == 16 ? 65535 : 255, o->ppm_ascii);
        break;
    case RT_FORMAT_BMP:
        st = bmp_write(path, px, width, height);
        break;
    case RT_FORMAT_PFM:
        st = pfm_write(path, px, width, height);
        break;
    case RT_FORMAT_EXR:
        st = exr_write(path, px, width, height);
        break;
    default:
        st = RT_EUNSUPPORTED;
    }
    free(px);
    return st;
}

int rt_image_write(const char *path, const int64_t *acc, uint32_t width, uint32_t height, uint32_t samples,
                   const rt_image_write_opts *o)
{
    return write_any(path, acc, width, height, samples, NULL, o);
}

int rt_image_write_rows(const char *path, const int64_t *acc, uint32_t width, uint32_t height,
                        const uint32_t *row_samples, const rt_image_write_opts *o)
{
    return write_any(path, acc, width, height, 0, row_samples, o);
}
