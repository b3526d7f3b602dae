/* image_write.h - every output format, chosen by the file's extension:
 * PNG (8/16-bit, libpng), PPM (binary P6 or the book's ASCII P3, 8/16-bit),
 * BMP (24-bit uncompressed), PFM and OpenEXR (linear float radiance,
 * unclamped, for compositing). One dispatcher (image_write.c), one file per
 * format (png.c, ppm.c, bmp.c, pfm.c, exr.c). Every writer is atomic: the
 * file appears complete or not at all. */
#ifndef RT_IMAGE_WRITE_H
#define RT_IMAGE_WRITE_H

#include <stdint.h>

typedef enum rt_image_format {
    RT_FORMAT_UNKNOWN = -1,
    RT_FORMAT_PNG = 0,
    RT_FORMAT_PPM = 1,
    RT_FORMAT_BMP = 2,
    RT_FORMAT_PFM = 3,
    RT_FORMAT_EXR = 4,
} rt_image_format;

/* A key and value the file records about how it was made (PNG text
 * chunks, EXR string attributes; the other formats have no place for
 * them). */
typedef struct rt_text {
    const char *key, *value;
} rt_text;

/* The format named by path's extension (case-insensitive), or
 * RT_FORMAT_UNKNOWN. */
rt_image_format rt_image_format_from_path(const char *path);
/* ".png, .ppm, .bmp, .pfm, .exr" for messages. */
const char *rt_image_format_list(void);
/* Whether this build writes the format (.exr needs OpenEXR): 1 or 0. */
int rt_image_format_available(rt_image_format id);

typedef struct rt_image_write_opts {
    int bit_depth;       /* 8 or 16 (PNG and PPM); ignored by float formats */
    int ppm_ascii;       /* PPM: write P3 text instead of binary P6 */
    const rt_text *text; /* what the file records */
    int n_text;
} rt_image_write_opts;

/* Checks that the options suit the format: RT_EUNSUPPORTED for 16 bits in
 * a BMP, PFM or EXR, P3 in anything but a PPM, or a format this build does
 * not write; RT_EINVAL for a bit depth
 * other than 8 or 16. */
int rt_image_check_opts(rt_image_format fmt, const rt_image_write_opts *o);

/* Writes the render's accumulation buffer (width*height*3 fixed-point sums
 * of `samples` samples, rows from the top) to path in the format its
 * extension names: 8/16-bit gamma-2 for PNG, PPM and BMP, linear float for
 * PFM and EXR. */
int rt_image_write(const char *path, const int64_t *acc, uint32_t width, uint32_t height, uint32_t samples,
                   const rt_image_write_opts *o);

/* As rt_image_write, but row y holds row_samples[y] samples (0: the row is
 * black): a progressive preview. */
int rt_image_write_rows(const char *path, const int64_t *acc, uint32_t width, uint32_t height,
                        const uint32_t *row_samples, const rt_image_write_opts *o);

#endif
