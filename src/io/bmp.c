/* bmp.c - BMP: 24-bit uncompressed, rows bottom-up. */
#include <stdlib.h>
#include <string.h>

#include "formats.h"
#include "status.h"

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
    rt_format_le32(h + 2, (uint32_t)total);
    rt_format_le32(h + 10, 54);        /* pixel data offset */
    rt_format_le32(h + 14, 40);        /* BITMAPINFOHEADER size */
    rt_format_le32(h + 18, width);
    rt_format_le32(h + 22, height);    /* positive: bottom-up */
    rt_format_le16(h + 26, 1);         /* planes */
    rt_format_le16(h + 28, 24);        /* bits per pixel */
    rt_format_le32(h + 34, (uint32_t)data);
    rt_format_le32(h + 38, 2835);      /* 72 dpi, as most writers put it */
    rt_format_le32(h + 42, 2835);
    rt_atomic_file f;
    int st = rt_format_start(&f, path, h, sizeof h);
    for (uint32_t y = height; y-- > 0 && !st;) {
        const uint8_t *src = rgb + (size_t)y * width * 3;
        for (uint32_t x = 0; x < width; x++) {
            row[3 * x] = src[3 * x + 2];
            row[3 * x + 1] = src[3 * x + 1];
            row[3 * x + 2] = src[3 * x];
        }
        st = rt_format_put(&f, row, (size_t)stride);
    }
    free(row);
    return st ? st : rt_atomic_commit(&f);
}


static int write_bmp(const char *path, const void *px, uint32_t width, uint32_t height, const rt_image_write_opts *o)
{
    (void)o;
    return bmp_write(path, px, width, height);
}

const rt_format rt_format_bmp = {.id = RT_FORMAT_BMP, .ext = ".bmp", .write = write_bmp};
