/* texture_image.c - image textures: reading the file, the size checks, the
 * type from the first bytes, and PNG through libpng. The JPEG reader is
 * texture_jpeg.c.
 *
 * A PNG's chunks are walked (lengths and CRCs) before libpng sees them, so
 * that a cut file, a bad CRC and the announced size each get their own
 * status, and a hostile size is refused before anything is allocated. */
#include "texture_image.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "fileio.h"
#include "status.h"
#include "texture_internal.h"

rt_texture_limits rt_texture_limits_default(void)
{
    return (rt_texture_limits){RT_TEXTURE_MAX_PIXELS, RT_TEXTURE_MAX_FILE_BYTES};
}

int rt_texture_check_size(uint64_t width, uint64_t height, const rt_texture_limits *lim)
{
    if (!width || !height)
        return RT_EIMAGE_EMPTY;
    /* Both are at most 2^32 - 1 (PNG) or 65535 (JPEG): no uint64 overflow. */
    if (width > UINT32_MAX || height > UINT32_MAX || width * height > UINT32_MAX)
        return RT_EOVERFLOW;
    return width * height > lim->max_pixels ? RT_EIMAGE_LIMIT : RT_OK;
}

int rt_texture_alloc(rt_texture_image *out, uint32_t width, uint32_t height)
{
    out->texels = malloc((size_t)width * height * 3);
    if (!out->texels)
        return RT_ENOMEM;
    out->width = width;
    out->height = height;
    return RT_OK;
}

void rt_texture_image_free(rt_texture_image *img)
{
    free(img->texels);
    *img = (rt_texture_image){0};
}

static uint32_t be32(const uint8_t *p) { return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]; }

/* Walks the chunks from the signature to IEND: RT_EIMAGE_TRUNCATED when one
 * runs past the end (or IEND never comes), RT_EIMAGE_CRC for a bad CRC,
 * RT_EIMAGE_CORRUPT when the first is not a 13-byte IHDR; its size in *w, *h. */
static int png_walk(const uint8_t *data, size_t len, uint32_t *w, uint32_t *h)
{
    size_t pos = 8;
    for (int first = 1;; first = 0) {
        if (len - pos < 8)
            return RT_EIMAGE_TRUNCATED;
        uint32_t n = be32(data + pos);
        const uint8_t *type = data + pos + 4;
        if (n > 0x7fffffffu)
            return RT_EIMAGE_CORRUPT;
        if (len - pos - 8 < (size_t)n + 4)
            return RT_EIMAGE_TRUNCATED;
        uLong crc = crc32(crc32(0L, Z_NULL, 0), type, 4 + n);
        if (crc != be32(type + 4 + n))
            return RT_EIMAGE_CRC;
        if (first) {
            if (memcmp(type, "IHDR", 4) || n != 13)
                return RT_EIMAGE_CORRUPT;
            *w = be32(type + 4);
            *h = be32(type + 8);
        }
        if (!memcmp(type, "IEND", 4))
            return RT_OK;
        pos += 12 + (size_t)n;
    }
}

typedef struct png_src {
    const uint8_t *data;
    size_t len, pos;
} png_src;

static void png_read_mem(png_structp png, png_bytep dst, size_t n)
{
    png_src *s = png_get_io_ptr(png);
    if (n > s->len - s->pos)
        png_error(png, "read past the end"); /* the walk makes this unreachable */
    memcpy(dst, s->data + s->pos, n);
    s->pos += n;
}

static void png_fail(png_structp png, png_const_charp msg)
{
    (void)msg; /* the walk has placed cuts and CRCs: what is left is corrupt */
    png_longjmp(png, 1);
}

static void png_quiet(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

/* libpng's transforms to 8-bit RGB; RT_OK when the rows come out w * 3. */
static int png_to_rgb8(png_structp png, png_infop info, uint32_t w)
{
    int color = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
    if (color == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    if (depth == 16)
        png_set_scale_16(png);
    png_set_strip_alpha(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    return png_get_rowbytes(png, info) == (size_t)w * 3 ? RT_OK : RT_EIMAGE_CORRUPT;
}

static int png_decode(const uint8_t *data, size_t len, const rt_texture_limits *lim, rt_texture_image *out)
{
    uint32_t w = 0, h = 0;
    int st = png_walk(data, len, &w, &h);
    if (st == RT_OK)
        st = rt_texture_check_size(w, h, lim);
    if (st != RT_OK)
        return st;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, png_fail, png_quiet);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    png_bytep *volatile rows = NULL;
    if (!png || !info) {
        png_destroy_read_struct(&png, &info, NULL);
        return RT_ENOMEM;
    }
    png_src src = {data, len, 0};
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        free(rows);
        rt_texture_image_free(out);
        return RT_EIMAGE_CORRUPT;
    }
    png_set_read_fn(png, &src, png_read_mem);
    /* The walk has checked the size against our limits; libpng's own
     * (1,000,000 a side) must not refuse first with another status. */
    png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
    png_read_info(png, info);
    st = png_to_rgb8(png, info, w);
    if (st == RT_OK)
        st = rt_texture_alloc(out, w, h);
    if (st == RT_OK && !(rows = malloc(sizeof *rows * h)))
        st = RT_ENOMEM;
    if (st == RT_OK) {
        for (uint32_t y = 0; y < h; y++)
            rows[y] = out->texels + (size_t)y * w * 3;
        png_read_image(png, rows);
        png_read_end(png, NULL);
    }
    png_destroy_read_struct(&png, &info, NULL);
    free(rows);
    if (st != RT_OK)
        rt_texture_image_free(out);
    return st;
}

int rt_texture_image_decode(const uint8_t *data, size_t len, const rt_texture_limits *limits, rt_texture_image *out)
{
    *out = (rt_texture_image){0};
    rt_texture_limits def = rt_texture_limits_default();
    const rt_texture_limits *lim = limits ? limits : &def;
    static const uint8_t png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (len >= 8 && !memcmp(data, png_sig, 8))
        return png_decode(data, len, lim, out);
    if (len >= 2 && data[0] == 0xff && data[1] == 0xd8)
        return rt_texture_jpeg_decode(data, len, lim, out);
    /* A cut signature is a truncated file, anything else not an image. */
    if (len < 8 && len > 0 && !memcmp(data, png_sig, len))
        return RT_EIMAGE_TRUNCATED;
    return RT_EIMAGE_TYPE;
}

int rt_texture_image_load(const char *path, const rt_texture_limits *limits, rt_texture_image *out)
{
    *out = (rt_texture_image){0};
    size_t max = limits ? limits->max_file_bytes : RT_TEXTURE_MAX_FILE_BYTES;
    char *buf = NULL;
    size_t len = 0;
    int st = rt_file_read_all(path, max, &buf, &len);
    if (st == RT_EIO && errno == ENOENT)
        st = RT_ENOFILE;
    if (st == RT_OK)
        st = rt_texture_image_decode((const uint8_t *)buf, len, limits, out);
    free(buf);
    return st;
}
