/* image_io.h - image files. PNG through libpng (8- or 16-bit RGB with text
 * chunks), written atomically. Kept out of the core library so that the
 * render core links neither libpng nor MPI. */
#ifndef RT_IMAGE_IO_H
#define RT_IMAGE_IO_H

#include <stdint.h>

typedef struct rt_text {
    const char *key, *value;
} rt_text;

/* rgb: width*height*3 samples, 8-bit (bit_depth 8, uint8_t) or 16-bit
 * (bit_depth 16, uint16_t in host order). */
int rt_png_write(const char *path, const void *rgb, uint32_t width, uint32_t height, int bit_depth,
                 const rt_text *text, int n_text);

/* Reads an 8-bit RGB PNG (for tests and tools); *rgb is malloc'd. */
int rt_png_read(const char *path, uint8_t **rgb, uint32_t *width, uint32_t *height);

#endif
