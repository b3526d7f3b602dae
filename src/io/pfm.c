/* pfm.c - PFM: linear float RGB, rows bottom-up. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats.h"
#include "status.h"

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
    int st = rt_format_start(&f, path, head, (size_t)hn);
    for (uint32_t y = height; y-- > 0 && !st;) {
        for (size_t i = 0; i < row_samples; i++) {
            uint32_t bits;
            memcpy(&bits, &rgb[(size_t)y * row_samples + i], 4);
            rt_format_le32(row + 4 * i, bits);
        }
        st = rt_format_put(&f, row, row_samples * 4);
    }
    free(row);
    return st ? st : rt_atomic_commit(&f);
}


static int write_pfm(const char *path, const void *px, uint32_t width, uint32_t height, const rt_image_write_opts *o)
{
    (void)o;
    return pfm_write(path, px, width, height);
}

const rt_format rt_format_pfm = {.id = RT_FORMAT_PFM, .ext = ".pfm", .linear = 1, .write = write_pfm};
