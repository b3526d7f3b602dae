/* formats.h - what the dispatcher (image_write.c) knows of each format
 * file, and the helpers they share. Inside io/ and its tests only. */
#ifndef RT_FORMATS_H
#define RT_FORMATS_H

#include <stddef.h>
#include <stdint.h>

#include "fileio.h"
#include "image_write.h"

/* Pixels as a writer takes them: width*height*3 samples, rows from the top. */
typedef enum rt_pixels {
    RT_PIXELS_RGB8,   /* gamma 2, uint8_t */
    RT_PIXELS_RGB16,  /* gamma 2, uint16_t in host order */
    RT_PIXELS_LINEAR, /* linear radiance, float */
} rt_pixels;

typedef struct rt_format {
    rt_image_format id;
    const char *ext; /* ".png" */
    int linear;      /* takes RT_PIXELS_LINEAR, else RT_PIXELS_RGB8 or RGB16 by bit depth */
    int deep;        /* can take 16 bits */
    int (*write)(const char *path, const void *px, uint32_t width, uint32_t height, const rt_image_write_opts *o);
} rt_format;

extern const rt_format rt_format_png, rt_format_ppm, rt_format_bmp, rt_format_pfm, rt_format_exr;

/* A PNG's zlib level (0-9) and the row filters libpng may choose from
 * (PNG_FILTER_NONE ... PNG_ALL_FILTERS of png.h, which are bits 3-7). */
typedef struct rt_png_params {
    int level;
    int filters;
} rt_png_params;

/* What the program writes: zlib level 4 with libpng's adaptive choice among
 * every filter. On a 1200x800 frame of the final scene it writes in about a
 * third of the time of zlib's default level 6 for a file 2.4 % larger;
 * levels 1-3 are not much faster and 10-16 % larger (tools/bench/bench_png,
 * docs/PERFORMANCE.md). */
#define RT_PNG_DEFAULT ((rt_png_params){.level = 4, .filters = 0xf8 /* PNG_ALL_FILTERS */})

/* PNG with text chunks, 8 or 16 bits (tests call it directly), at
 * RT_PNG_DEFAULT or at the given parameters (tools/bench/bench_png.c). */
int rt_png_write(const char *path, const void *rgb, uint32_t width, uint32_t height, int bit_depth,
                 const rt_text *text, int n_text);
int rt_png_write_with(const char *path, const void *rgb, uint32_t width, uint32_t height, int bit_depth,
                      const rt_text *text, int n_text, rt_png_params params);

/* Writes n bytes or aborts f; returns the status. */
int rt_format_put(rt_atomic_file *f, const void *p, size_t n);
/* Opens the atomic file and writes the header; on failure nothing is left
 * and f needs no cleanup. */
int rt_format_start(rt_atomic_file *f, const char *path, const void *header, size_t n);
/* Little-endian 16- and 32-bit values into bytes (BMP headers, PFM). */
static inline void rt_format_le16(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}
static inline void rt_format_le32(uint8_t *p, uint32_t v)
{
    rt_format_le16(p, v);
    rt_format_le16(p + 2, v >> 16);
}
/* The status of the failed call that set errno. */
int rt_format_io_status(void);

#endif
