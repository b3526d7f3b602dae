/* ppm.c - PPM: binary P6 or the book's ASCII P3, 8 or 16 bits. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats.h"
#include "status.h"

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
    int st = rt_format_start(&f, path, head, (size_t)hn);
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
                    st = rt_format_io_status();
                    rt_atomic_abort(&f);
                }
            }
        } else if (wide) {
            for (size_t i = 0; i < row_samples; i++) { /* PPM's 16-bit samples are big-endian */
                row[2 * i] = (uint8_t)(p16[base + i] >> 8);
                row[2 * i + 1] = (uint8_t)p16[base + i];
            }
            st = rt_format_put(&f, row, row_samples * 2);
        } else {
            st = rt_format_put(&f, p8 + base, row_samples);
        }
    }
    free(row);
    return st ? st : rt_atomic_commit(&f);
}


static int write_ppm(const char *path, const void *px, uint32_t width, uint32_t height, const rt_image_write_opts *o)
{
    return ppm_write(path, px, width, height, o->bit_depth == 16 ? 65535 : 255, o->ppm_ascii);
}

const rt_format rt_format_ppm = {.id = RT_FORMAT_PPM, .ext = ".ppm", .deep = 1, .write = write_ppm};
