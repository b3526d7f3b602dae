/* image_write.c - the output formats' dispatcher: the format from the
 * extension, the options checked against it, the sums tone-mapped (or kept
 * linear) into the pixels the format takes, then its writer. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "formats.h"
#include "image.h"
#include "rt_config.h"
#include "status.h"

#if !RT_HAVE_EXR
/* Built without OpenEXR: the extension is still known, so that a .exr
 * output is refused as a missing feature rather than an unknown type. */
static const rt_format exr_missing = {.id = RT_FORMAT_EXR, .ext = ".exr", .linear = 1};
#define rt_format_exr exr_missing
#endif

static const rt_format *const FORMATS[] = {&rt_format_png, &rt_format_ppm, &rt_format_bmp, &rt_format_pfm,
                                           &rt_format_exr};
#define N_FORMATS (sizeof FORMATS / sizeof FORMATS[0])

static const rt_format *format_of(rt_image_format id)
{
    for (size_t i = 0; i < N_FORMATS; i++)
        if (FORMATS[i]->id == id)
            return FORMATS[i];
    return NULL;
}

rt_image_format rt_image_format_from_path(const char *path)
{
    size_t n = strlen(path);
    for (size_t i = 0; i < N_FORMATS; i++) {
        size_t e = strlen(FORMATS[i]->ext);
        if (n > e && !strcasecmp(path + n - e, FORMATS[i]->ext))
            return FORMATS[i]->id;
    }
    return RT_FORMAT_UNKNOWN;
}

const char *rt_image_format_list(void) { return ".png, .ppm, .bmp, .pfm, .exr"; }

int rt_image_format_available(rt_image_format id)
{
    const rt_format *f = format_of(id);
    return f && f->write;
}

int rt_image_check_opts(rt_image_format id, const rt_image_write_opts *o)
{
    const rt_format *f = format_of(id);
    if (o->bit_depth != 8 && o->bit_depth != 16)
        return RT_EINVAL;
    if (!f || !f->write || (o->bit_depth == 16 && !f->deep) || (o->ppm_ascii && id != RT_FORMAT_PPM))
        return RT_EUNSUPPORTED;
    return RT_OK;
}

int rt_format_io_status(void) { return rt_status_from_errno(errno); }

int rt_format_put(rt_atomic_file *f, const void *p, size_t n)
{
    if (fwrite(p, 1, n, f->fp) == n)
        return RT_OK;
    int st = rt_format_io_status();
    rt_atomic_abort(f);
    return st;
}

int rt_format_start(rt_atomic_file *f, const char *path, const void *header, size_t n)
{
    int st = rt_atomic_open(f, path);
    return st ? st : rt_format_put(f, header, n);
}

/* Tone maps (or keeps linear) row by row: rows may hold different numbers
 * of samples in a preview. */
static void convert_rows(const int64_t *acc, uint32_t width, uint32_t height, uint32_t samples,
                         const uint32_t *row_samples, rt_pixels kind, uint8_t *px, size_t elem)
{
    const size_t row = (size_t)width * 3;
    for (uint32_t y = 0; y < height; y++) {
        uint32_t n = row_samples ? row_samples[y] : samples;
        const int64_t *src = acc + y * row;
        void *dst = px + y * row * elem;
        if (!n)
            memset(dst, 0, row * elem); /* also 0.0f */
        else if (kind == RT_PIXELS_LINEAR)
            rt_image_to_linear(src, width, n, dst);
        else if (kind == RT_PIXELS_RGB16)
            rt_image_to_rgb16(src, width, n, dst);
        else
            rt_image_to_rgb8(src, width, n, dst);
    }
}

static int write_any(const char *path, const int64_t *acc, uint32_t width, uint32_t height, uint32_t samples,
                     const uint32_t *row_samples, const rt_image_write_opts *o)
{
    rt_image_format id = rt_image_format_from_path(path);
    int st = rt_image_check_opts(id, o);
    if (st)
        return st;
    if (!width || !height || (!row_samples && !samples))
        return RT_EINVAL;
    const rt_format *f = format_of(id);
    const rt_pixels kind = f->linear ? RT_PIXELS_LINEAR : o->bit_depth == 16 ? RT_PIXELS_RGB16 : RT_PIXELS_RGB8;
    const size_t elem = kind == RT_PIXELS_LINEAR ? sizeof(float) : kind == RT_PIXELS_RGB16 ? sizeof(uint16_t) : 1;
    void *px = malloc((size_t)width * height * 3 * elem);
    if (!px)
        return RT_ENOMEM;
    convert_rows(acc, width, height, samples, row_samples, kind, px, elem);
    st = f->write(path, px, width, height, o);
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
