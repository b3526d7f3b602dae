/* png.c - PNG through libpng, 8 or 16 bits with text chunks; every libpng error
 * is caught (setjmp) and turned into a status, and a failed write leaves no
 * file behind. zlib's level and the row filters: RT_PNG_DEFAULT (formats.h). */
#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"
#include "formats.h"
#include "status.h"

static void png_err(png_structp png, png_const_charp msg)
{
    (void)msg; /* reported as RT_EPNG by the caller; modules never print */
    png_longjmp(png, 1);
}
static void png_warn(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

int rt_png_write_with(const char *path, const void *rgb, uint32_t width, uint32_t height, int bit_depth,
                      const rt_text *text, int n_text, rt_png_params params)
{
    if (!width || !height || (bit_depth != 8 && bit_depth != 16) || width > PNG_USER_WIDTH_MAX ||
        height > PNG_USER_HEIGHT_MAX || params.level < 0 || params.level > 9 || !(params.filters & PNG_ALL_FILTERS) ||
        (params.filters & ~PNG_ALL_FILTERS))
        return RT_EINVAL;
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (st)
        return st;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, png_err, png_warn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_textp chunks = n_text > 0 ? calloc((size_t)n_text, sizeof *chunks) : NULL;
    if (!png || !info || (n_text > 0 && !chunks)) {
        png_destroy_write_struct(&png, &info);
        free(chunks);
        rt_atomic_abort(&f);
        return RT_ENOMEM;
    }
    if (setjmp(png_jmpbuf(png))) {
        /* libpng reports a failed fwrite as a generic "Write Error". */
        int full = rt_status_from_errno(errno) == RT_ENOSPACE;
        png_destroy_write_struct(&png, &info);
        free(chunks);
        rt_atomic_abort(&f);
        return full ? RT_ENOSPACE : RT_EPNG;
    }
    png_init_io(png, f.fp);
    png_set_compression_level(png, params.level);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, params.filters);
    png_set_IHDR(png, info, width, height, bit_depth, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    for (int i = 0; i < n_text; i++) {
        chunks[i].compression = PNG_TEXT_COMPRESSION_NONE;
        chunks[i].key = (png_charp)text[i].key;
        chunks[i].text = (png_charp)text[i].value;
    }
    if (n_text > 0)
        png_set_text(png, info, chunks, n_text);
    png_write_info(png, info);
    if (bit_depth == 16)
        png_set_swap(png); /* PNG is big-endian; our buffer is host order */
    size_t stride = (size_t)width * 3 * (size_t)(bit_depth / 8);
    for (uint32_t y = 0; y < height; y++)
        png_write_row(png, (png_const_bytep)rgb + (size_t)y * stride);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    free(chunks);
    return rt_atomic_commit(&f);
}

int rt_png_write(const char *path, const void *rgb, uint32_t width, uint32_t height, int bit_depth,
                 const rt_text *text, int n_text)
{
    return rt_png_write_with(path, rgb, width, height, bit_depth, text, n_text, RT_PNG_DEFAULT);
}

static int write_png(const char *path, const void *px, uint32_t width, uint32_t height, const rt_image_write_opts *o)
{
    return rt_png_write(path, px, width, height, o->bit_depth, o->text, o->n_text);
}

const rt_format rt_format_png = {.id = RT_FORMAT_PNG, .ext = ".png", .deep = 1, .write = write_png};
